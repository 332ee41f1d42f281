#include "scene_json.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Geometry>

#include "idto/contact/contact_engine.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/multibody/data.hpp"

namespace idto::viz_internal {
namespace {

// Model colours: no pure red or green, which the force arrows use.
const char* const kModelColors[] = {"#4e79a7", "#f28e2b", "#b07aa1", "#76b7b2",
                                    "#9c755f", "#edc948", "#ff9da7", "#bab0ac"};
constexpr int kNumModelColors = sizeof(kModelColors) / sizeof(kModelColors[0]);
const char kWorldColor[] = "#8c8c8c";

// Appends compact JSON numbers: `decimals` digits after the point, trailing zeros dropped.
class NumberWriter {
 public:
  explicit NumberWriter(std::string* out) : out_(out) {}
  void Number(double x, int decimals = 6) {
    if (!std::isfinite(x)) {
      out_->append("null");
      return;
    }
    char buffer[64];
    const double magnitude = std::abs(x);
    int n = 0;
    if (magnitude != 0.0 && (magnitude >= 1e12 || magnitude < std::pow(10.0, -decimals))) {
      n = std::snprintf(buffer, sizeof(buffer), "%.6e", x);
    } else {
      n = std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, x);
      if (std::string(buffer, n).find('.') != std::string::npos) {
        while (n > 0 && buffer[n - 1] == '0') --n;
        if (n > 0 && buffer[n - 1] == '.') --n;
      }
      if (n == 2 && buffer[0] == '-' && buffer[1] == '0') {
        buffer[0] = '0';
        n = 1;
      }
    }
    out_->append(buffer, static_cast<std::size_t>(n));
  }
  // [x0, x1, ...]
  void Array(const double* x, int size, int decimals = 6) {
    out_->push_back('[');
    for (int i = 0; i < size; ++i) {
      if (i) out_->push_back(',');
      Number(x[i], decimals);
    }
    out_->push_back(']');
  }

 private:
  std::string* out_;
};

// Position and quaternion (x, y, z, w: three.js order) of a pose: 7 numbers.
void AppendPose(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, std::vector<double>* out) {
  Eigen::Quaterniond Q(R);
  Q.normalize();
  out->insert(out->end(), {p.x(), p.y(), p.z(), Q.x(), Q.y(), Q.z(), Q.w()});
}

// For each body, the index of its model: the subtree of each child of the world (in body
// order) is one model; -1 for the world.
std::vector<int> ModelOfBody(const Model& model, std::vector<BodyIndex>* roots) {
  std::vector<int> model_of(model.num_bodies(), -1);
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    BodyIndex root = b;
    while (model.parent(root) > 0) root = model.parent(root);
    const auto it = std::find(roots->begin(), roots->end(), root);
    model_of[b] = static_cast<int>(it - roots->begin());
    if (it == roots->end()) roots->push_back(root);
  }
  return model_of;
}

// Bodies whose pose depends on q (not welded to the world).
std::vector<BodyIndex> AnimatedBodies(const Model& model) {
  std::vector<BodyIndex> animated;
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    if (model.mobilized_body(b) != kWorldBody) animated.push_back(b);
  }
  return animated;
}

// Bounding radius of a shape about its frame origin (0 for half-spaces).
double BoundingRadius(const Shape& shape) {
  if (const auto* s = std::get_if<Sphere>(&shape)) return s->radius;
  if (const auto* c = std::get_if<Capsule>(&shape)) return c->radius + 0.5 * c->length;
  if (const auto* y = std::get_if<Cylinder>(&shape)) return std::hypot(y->radius, 0.5 * y->length);
  if (const auto* b = std::get_if<Box>(&shape)) return 0.5 * b->size.norm();
  return 0.0;
}

void AppendGeometry(const GeometryInstance& g, int model_index, NumberWriter* w, std::string* out) {
  out->append("{\"name\":").append(JsonQuote(g.name));
  out->append(",\"body\":").append(std::to_string(g.body));
  out->append(",\"type\":\"").append(ShapeName(g.shape)).append("\"");
  if (const auto* s = std::get_if<Sphere>(&g.shape)) {
    out->append(",\"radius\":");
    w->Number(s->radius);
  } else if (const auto* capsule = std::get_if<Capsule>(&g.shape)) {
    out->append(",\"radius\":");
    w->Number(capsule->radius);
    out->append(",\"length\":");
    w->Number(capsule->length);
  } else if (const auto* cylinder = std::get_if<Cylinder>(&g.shape)) {
    out->append(",\"radius\":");
    w->Number(cylinder->radius);
    out->append(",\"length\":");
    w->Number(cylinder->length);
  } else if (const auto* b = std::get_if<Box>(&g.shape)) {
    out->append(",\"size\":");
    w->Array(b->size.data(), 3);
  }
  std::vector<double> pose;
  AppendPose(g.X_BG.linear(), g.X_BG.translation(), &pose);
  out->append(",\"pose\":");
  w->Array(pose.data(), 7);
  out->append(",\"color\":\"")
      .append(model_index < 0 ? kWorldColor : kModelColors[model_index % kNumModelColors])
      .append("\"}");
}

// A drawn contact: point, normal force, friction force (on the body shown), signed distance.
struct DrawnContact {
  Eigen::Vector3d p, fn, ft;
  double phi;
};

// Contacts of one frame with a force of at least min_force, each as the force on the moving
// body of the pair (B, unless only A moves).
void CollectContacts(const Model& model, const ContactEngine& engine, const ContactData& cd,
                     double min_force, std::vector<DrawnContact>* out) {
  out->clear();
  for (int i = 0; i < cd.num_active; ++i) {
    const ContactResult& r = cd.results[i];
    if (r.force.f.norm() < min_force) continue;
    const ContactPair& pair = engine.pairs()[r.pair];
    const bool b_static = model.mobilized_body(pair.body_b) == kWorldBody;
    const bool a_static = model.mobilized_body(pair.body_a) == kWorldBody;
    const double sign = (b_static && !a_static) ? -1.0 : 1.0;
    out->push_back({r.p_WC, sign * r.force.fn * r.normal_W, sign * r.force.ft, r.phi});
  }
}

// Everything measured per displayed frame.
struct FrameData {
  std::vector<std::vector<double>> poses;  // per frame: 7 per animated body
  std::vector<std::vector<double>> ghost;  // per frame: 7 per animated body, or empty
  std::vector<std::vector<DrawnContact>> contacts;
  std::vector<double> static_poses;  // 7 per body (constant for static bodies)
  Eigen::Vector3d lower{Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity())};
  Eigen::Vector3d upper{-Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity())};
  double max_force{0.0};
};

void Grow(const Eigen::Vector3d& p, double r, FrameData* fd) {
  fd->lower = fd->lower.cwiseMin(p - Eigen::Vector3d::Constant(r));
  fd->upper = fd->upper.cwiseMax(p + Eigen::Vector3d::Constant(r));
}

double MinForce(const Model& model, const HtmlAnimationOptions& options) {
  if (options.min_force >= 0.0) return options.min_force;
  const double weight = model.total_mass() * model.gravity().norm();
  return weight > 0.0 ? 1e-3 * weight : 1e-3;
}

FrameData Measure(const Model& model, const std::vector<AnimationFrame>& frames,
                  const std::vector<int>& selected, const HtmlAnimationOptions& options) {
  FrameData fd;
  Data data(model);
  const std::vector<BodyIndex> animated = AnimatedBodies(model);
  std::vector<double> body_radius(model.num_bodies(), 0.0);
  for (const GeometryInstance& g : model.geometries()) {
    body_radius[g.body] =
        std::max(body_radius[g.body], g.X_BG.translation().norm() + BoundingRadius(g.shape));
  }
  std::optional<ContactEngine> engine;
  ContactData cd;
  if (options.contact) {
    engine.emplace(model, *options.contact);
    cd = engine->MakeData(model);
  }
  const double min_force = MinForce(model, options);
  const Eigen::VectorXd zero_v = Eigen::VectorXd::Zero(model.nv());
  for (int k : selected) {
    const AnimationFrame& f = frames[k];
    ForwardKinematics(model, f.q, f.v.size() ? f.v : zero_v, &data);
    if (fd.static_poses.empty()) {
      for (BodyIndex b = 0; b < model.num_bodies(); ++b) {
        AppendPose(data.R_WB(b), data.p_WB(b), &fd.static_poses);
        if (model.mobilized_body(b) == kWorldBody && body_radius[b] > 0.0) {
          Grow(data.p_WB(b), body_radius[b], &fd);
        }
      }
    }
    fd.poses.emplace_back();
    for (BodyIndex b : animated) {
      AppendPose(data.R_WB(b), data.p_WB(b), &fd.poses.back());
      Grow(data.p_WB(b), body_radius[b], &fd);
    }
    fd.contacts.emplace_back();
    if (engine) {
      engine->Evaluate(model, data, &cd);
      CollectContacts(model, *engine, cd, min_force, &fd.contacts.back());
      for (const DrawnContact& c : fd.contacts.back()) {
        fd.max_force = std::max({fd.max_force, c.fn.norm(), c.ft.norm()});
      }
    }
    fd.ghost.emplace_back();
    if (f.q_ghost.size()) {
      ForwardKinematics(model, f.q_ghost, &data);
      for (BodyIndex b : animated) AppendPose(data.R_WB(b), data.p_WB(b), &fd.ghost.back());
    }
  }
  return fd;
}

void AppendBodies(const Model& model, const std::vector<int>& model_of, const FrameData& fd,
                  NumberWriter* w, std::string* out) {
  out->append(",\"bodies\":[");
  for (BodyIndex b = 0; b < model.num_bodies(); ++b) {
    if (b) out->push_back(',');
    out->append("{\"name\":").append(JsonQuote(model.body_name(b)));
    out->append(",\"model\":").append(std::to_string(model_of[b]));
    out->append(",\"pose\":");
    w->Array(fd.static_poses.data() + 7 * b, 7);
    out->push_back('}');
  }
  out->append("],\"animated\":[");
  const std::vector<BodyIndex> animated = AnimatedBodies(model);
  for (std::size_t i = 0; i < animated.size(); ++i) {
    out->append(i ? "," : "").append(std::to_string(animated[i]));
  }
  out->append("],\"geometries\":[");
  for (std::size_t i = 0; i < model.geometries().size(); ++i) {
    const GeometryInstance& g = model.geometries()[i];
    if (i) out->push_back(',');
    AppendGeometry(g, model_of[g.body], w, out);
  }
  out->push_back(']');
}

// Bones: a segment from each body's origin to the origins of its children (joints other than
// floating and planar ones) and of its shapes, fixed in the body: the links of a model show even
// where they have no collision geometry.
void AppendBones(const Model& model, NumberWriter* w, std::string* out) {
  out->append(",\"bones\":[");
  bool first = true;
  const auto bone = [&](BodyIndex body, const Eigen::Vector3d& to) {
    if (body == kWorldBody || to.norm() < 1e-6) return;
    out->append(first ? "" : ",").append("{\"body\":").append(std::to_string(body));
    out->append(",\"to\":");
    w->Array(to.data(), 3);
    out->push_back('}');
    first = false;
  };
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const JointType type = model.joint_type(b);
    if (type != JointType::kFloating && type != JointType::kPlanar) {
      bone(model.parent(b), model.joint_frame_in_parent(b).translation());
    }
  }
  for (const GeometryInstance& g : model.geometries()) {
    if (!std::holds_alternative<HalfSpace>(g.shape)) bone(g.body, g.X_BG.translation());
  }
  out->push_back(']');
}

void AppendFrames(const std::vector<AnimationFrame>& frames, const std::vector<int>& selected,
                  const FrameData& fd, NumberWriter* w, std::string* out) {
  out->append(",\"times\":[");
  for (std::size_t i = 0; i < selected.size(); ++i) {
    if (i) out->push_back(',');
    w->Number(frames[selected[i]].t, 9);
  }
  out->append("],\"poses\":[");
  for (std::size_t i = 0; i < fd.poses.size(); ++i) {
    if (i) out->push_back(',');
    w->Array(fd.poses[i].data(), static_cast<int>(fd.poses[i].size()));
  }
  out->append("],\"ghost\":[");
  for (std::size_t i = 0; i < fd.ghost.size(); ++i) {
    if (i) out->push_back(',');
    w->Array(fd.ghost[i].data(), static_cast<int>(fd.ghost[i].size()));
  }
  out->append("],\"contacts\":[");
  std::vector<double> flat;
  for (std::size_t i = 0; i < fd.contacts.size(); ++i) {
    flat.clear();
    for (const DrawnContact& c : fd.contacts[i]) {
      flat.insert(flat.end(), {c.p.x(), c.p.y(), c.p.z(), c.fn.x(), c.fn.y(), c.fn.z(), c.ft.x(),
                               c.ft.y(), c.ft.z(), c.phi});
    }
    if (i) out->push_back(',');
    w->Array(flat.data(), static_cast<int>(flat.size()));
  }
  out->push_back(']');
}

}  // namespace

std::string JsonQuote(const std::string& text) {
  std::string out = "\"";
  for (unsigned char c : text) {
    if (c == '"' || c == '\\') {
      out.push_back('\\');
      out.push_back(static_cast<char>(c));
    } else if (c < 0x20 || c == '<' || c == '>' || c == '&') {
      char buffer[8];
      std::snprintf(buffer, sizeof(buffer), "\\u%04x", c);
      out.append(buffer);
    } else {
      out.push_back(static_cast<char>(c));
    }
  }
  return out + "\"";
}

std::vector<int> SelectFrames(const std::vector<AnimationFrame>& frames, double max_frame_rate) {
  // Keep the first frame at or after each point of the grid t_0 + j / max_frame_rate.
  const double gap = 1.0 / max_frame_rate;
  const double t0 = frames.front().t;
  const int last = static_cast<int>(frames.size()) - 1;
  std::vector<int> selected{0};
  double next = t0 + gap;
  for (int k = 1; k < last; ++k) {
    if (frames[k].t >= next - 1e-9 * gap) {
      selected.push_back(k);
      next = t0 + (std::floor((frames[k].t - t0) / gap + 1e-9) + 1.0) * gap;
    }
  }
  if (last > 0) {
    // The last frame replaces a kept frame that is much closer to it than the gap.
    if (selected.size() > 1 && frames[last].t - frames[selected.back()].t < 0.5 * gap) {
      selected.pop_back();
    }
    selected.push_back(last);
  }
  return selected;
}

std::string MakeSceneJson(const Model& model, const std::vector<AnimationFrame>& frames,
                          const std::vector<int>& selected, const HtmlAnimationOptions& options) {
  std::vector<BodyIndex> roots;
  const std::vector<int> model_of = ModelOfBody(model, &roots);
  const FrameData fd = Measure(model, frames, selected, options);
  std::string out;
  out.reserve(64 * selected.size() * (1 + AnimatedBodies(model).size()));
  NumberWriter w(&out);
  out.append("{\"title\":").append(JsonQuote(options.title));
  out.append(",\"models\":[");
  for (std::size_t i = 0; i < roots.size(); ++i) {
    out.append(i ? "," : "").append("{\"name\":").append(JsonQuote(model.body_name(roots[i])));
    out.append(",\"color\":\"").append(kModelColors[i % kNumModelColors]).append("\"}");
  }
  out.append("]");
  AppendBodies(model, model_of, fd, &w, &out);
  AppendBones(model, &w, &out);
  // The scene's extent, for the camera, the grid and the force scale.
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 1.0;
  if (fd.lower.allFinite() && fd.upper.allFinite()) {
    center = 0.5 * (fd.lower + fd.upper);
    radius = std::max(0.5 * (fd.upper - fd.lower).norm(), 0.05);
  }
  const double force_scale = options.force_scale > 0.0 ? options.force_scale
                             : fd.max_force > 0.0
                                 ? 0.5 * radius / fd.max_force
                                 : 0.5 * radius / std::max(MinForce(model, options) * 1e3, 1e-9);
  out.append(",\"center\":");
  w.Array(center.data(), 3);
  out.append(",\"radius\":");
  w.Number(radius);
  out.append(",\"force_scale\":");
  w.Number(force_scale, 9);
  out.append(",\"max_force\":");
  w.Number(fd.max_force, 4);
  out.append(",\"has_contact_model\":").append(options.contact ? "true" : "false");
  out.append(",\"speed\":");
  w.Number(options.playback_speed);
  out.append(",\"show\":{\"forces\":").append(options.show_forces ? "true" : "false");
  out.append(",\"ghost\":").append(options.show_ghost ? "true" : "false");
  out.append(",\"frames\":").append(options.show_frames ? "true" : "false").append("}");
  AppendFrames(frames, selected, fd, &w, &out);
  out.append("}");
  return out;
}

}  // namespace idto::viz_internal
