// The `scene` section: URDF models (resolved over the share folders), extra world geometry,
// gravity; the contact options are read by contact_section.cpp.

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "config_loader.hpp"
#include "idto/core/errors.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "idto/parsers/urdf.hpp"

namespace idto::config_internal {

namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kSceneKeys = {"models", "geometry", "gravity", "enable_contact",
                                             "contact"};
const std::vector<std::string> kModelKeys = {"urdf",   "base",       "position",
                                             "rpy",    "quaternion", "planar_normal",
                                             "prefix", "name",       "inscribed_spheres"};
const std::vector<std::string> kGeometryKeys = {
    "name",     "shape", "radius",     "length", "size",
    "position", "rpy",   "quaternion", "body",   "inscribed_spheres"};
const std::vector<std::string> kInscribedSpheresKeys = {"num_per_axis", "radius_fraction",
                                                        "center_sphere"};

/// URDF roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Matrix3d RpyToRotation(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// position [3], and rpy [3] or quaternion [w, x, y, z] (not both).
Eigen::Isometry3d ReadPose(const Reader& reader, const MapReader& map) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  if (map.Has("position")) {
    X.translation() = reader.Vector3(map.Get("position"), map.Path("position"));
  }
  if (map.Has("rpy") && map.Has("quaternion")) {
    reader.Fail(map.Get("quaternion"), map.Path("quaternion"),
                "given together with rpy; expected one orientation (rpy or quaternion)");
  }
  if (map.Has("rpy")) {
    X.linear() = RpyToRotation(reader.Vector3(map.Get("rpy"), map.Path("rpy")));
  } else if (map.Has("quaternion")) {
    const Eigen::VectorXd w = reader.Vector(map.Get("quaternion"), map.Path("quaternion"), 4);
    if (!(w.norm() > 1e-12)) {
      reader.FailValue(map.Get("quaternion"), map.Path("quaternion"), "a zero quaternion",
                       "a non-zero quaternion [w, x, y, z] (normalized on use)");
    }
    X.linear() = Eigen::Quaterniond(w(0), w(1), w(2), w(3)).normalized().toRotationMatrix();
  }
  return X;
}

/// Search folders for URDF files: the given share folders, then two levels above the YAML file.
std::string ResolveUrdf(const std::string& urdf, const std::string& base_dir,
                        const std::vector<std::string>& share_dirs,
                        std::vector<std::string>* searched) {
  const fs::path p(urdf);
  std::vector<fs::path> candidates;
  if (p.is_absolute()) {
    candidates.push_back(p);
  } else {
    candidates.push_back(fs::path(base_dir) / p);
    std::vector<fs::path> dirs(share_dirs.begin(), share_dirs.end());
    dirs.push_back(fs::path(base_dir) / ".." / "..");
    for (const fs::path& dir : dirs) {
      candidates.push_back(dir / "models" / p);
      candidates.push_back(dir / p);
    }
  }
  for (const fs::path& c : candidates) {
    const fs::path normal = c.lexically_normal();
    std::error_code ec;
    if (fs::is_regular_file(normal, ec)) return normal.string();
    searched->push_back(normal.string());
  }
  return "";
}

/// `inscribed_spheres`: true (InscribedSpheresOptions{}), false (none), or a map
/// {num_per_axis, radius_fraction, center_sphere} (enabled, unspecified keys at their defaults).
std::optional<InscribedSpheresOptions> ReadInscribedSpheres(const Reader& reader,
                                                            const YAML::Node& node,
                                                            const std::string& path) {
  const std::string expected =
      "true, false or a map {num_per_axis: integer >= 2, radius_fraction: number in (0, 0.5], "
      "center_sphere: bool}";
  if (node.IsScalar()) {
    bool enabled = false;
    if (!YAML::convert<bool>::decode(node, enabled)) {
      reader.FailValue(node, path, Describe(node), expected);
    }
    if (!enabled) return std::nullopt;
    return InscribedSpheresOptions{};
  }
  if (!node.IsMap()) reader.FailValue(node, path, Describe(node), expected);
  const MapReader m(reader, node, path, kInscribedSpheresKeys);
  InscribedSpheresOptions options;
  options.num_per_axis = m.Int("num_per_axis", options.num_per_axis, 2);
  if (options.num_per_axis > 100) {
    reader.FailValue(m.Get("num_per_axis"), m.Path("num_per_axis"),
                     std::to_string(options.num_per_axis), "an integer from 2 to 100");
  }
  options.radius_fraction = m.Double("radius_fraction", options.radius_fraction);
  if (!(options.radius_fraction > 0.0 && options.radius_fraction <= 0.5)) {
    reader.FailValue(m.Get("radius_fraction"), m.Path("radius_fraction"),
                     FormatValue(options.radius_fraction),
                     "a number in (0, 0.5] (sphere radius / smallest box side)");
  }
  options.center_sphere = m.Bool("center_sphere", options.center_sphere);
  return options;
}

}  // namespace

void ConfigLoader::LoadScene(const YAML::Node& node, const std::string& path) {
  const MapReader scene(reader_, node, path, kSceneKeys);
  ModelBuilder builder(config_.name);
  const YAML::Node models = scene.Require("models");
  if (!models.IsSequence() || models.size() == 0) {
    reader_.FailValue(models, scene.Path("models"), Describe(models),
                      "a non-empty list of models {urdf: file, base: fixed|floating|planar, "
                      "...}");
  }
  for (std::size_t i = 0; i < models.size(); ++i) {
    LoadModel(MapReader(reader_, models[i], At(scene.Path("models"), i), kModelKeys), &builder);
  }
  if (scene.Has("geometry")) {
    const YAML::Node geometry = scene.Get("geometry");
    if (!geometry.IsSequence()) {
      reader_.FailValue(geometry, scene.Path("geometry"), Describe(geometry),
                        "a list of geometries {name, shape, ...}");
    }
    for (std::size_t i = 0; i < geometry.size(); ++i) {
      LoadGeometry(MapReader(reader_, geometry[i], At(scene.Path("geometry"), i), kGeometryKeys),
                   &builder);
    }
  }
  if (scene.Has("gravity")) {
    builder.SetGravity(reader_.Vector3(scene.Get("gravity"), scene.Path("gravity")));
  }
  try {
    config_.model = builder.Build();
  } catch (const std::exception& e) {
    reader_.Fail(scene.node(), "scene", std::string("the scene is not a valid model: ") + e.what());
  }
  enable_contact_ = scene.Bool("enable_contact", true);
  if (scene.Has("contact")) LoadContact(scene.Get("contact"), scene.Path("contact"));
}

void ConfigLoader::LoadModel(const MapReader& m, ModelBuilder* builder) {
  SceneModelConfig model;
  const std::string urdf = reader_.String(m.Require("urdf"), m.Path("urdf"));
  std::vector<std::string> searched;
  model.urdf_file = ResolveUrdf(urdf, base_dir_, share_dirs_, &searched);
  if (model.urdf_file.empty()) {
    reader_.Fail(m.Get("urdf"), m.Path("urdf"),
                 "cannot find URDF file '" + urdf + "'; searched " + JoinNames(searched));
  }
  model.options.base = static_cast<BaseType>(
      m.Enum("base", {"fixed", "floating", "planar"}, static_cast<int>(BaseType::kFixed)));
  static_assert(static_cast<int>(BaseType::kFixed) == 0 &&
                    static_cast<int>(BaseType::kFloating) == 1 &&
                    static_cast<int>(BaseType::kPlanar) == 2,
                "BaseType order");
  model.options.X_WB = ReadPose(reader_, m);
  if (m.Has("planar_normal")) {
    if (model.options.base != BaseType::kPlanar) {
      reader_.Fail(m.Get("planar_normal"), m.Path("planar_normal"),
                   "given for a base that is not planar; expected base: planar");
    }
    const Eigen::Vector3d n = reader_.Vector3(m.Get("planar_normal"), m.Path("planar_normal"));
    if (!(n.norm() > 1e-12)) {
      reader_.FailValue(m.Get("planar_normal"), m.Path("planar_normal"), "a zero vector",
                        "a non-zero vector");
    }
    model.options.planar_normal = n.normalized();
  }
  model.options.prefix = m.String("prefix", "");
  model.options.model_name = m.String("name", "");
  if (m.Has("inscribed_spheres")) {
    model.options.box_inscribed_spheres =
        ReadInscribedSpheres(reader_, m.Get("inscribed_spheres"), m.Path("inscribed_spheres"));
  }
  try {
    // What the file holds that idto ignores by design is kept for the caller (idto-run prints it).
    AddUrdfFile(model.urdf_file, model.options, builder, &config_.urdf_warnings);
  } catch (const std::exception& e) {
    reader_.Fail(m.Get("urdf"), m.Path("urdf"),
                 "cannot load '" + model.urdf_file + "': " + e.what());
  }
  config_.models.push_back(std::move(model));
}

void ConfigLoader::LoadGeometry(const MapReader& g, ModelBuilder* builder) {
  const std::string name = reader_.String(g.Require("name"), g.Path("name"));
  const int type = reader_.Enum(g.Require("shape"), g.Path("shape"),
                                {"sphere", "capsule", "cylinder", "box", "half_space"});
  // The keys each shape takes.
  const std::vector<std::vector<std::string>> kShapeKeys = {
      {"radius"}, {"radius", "length"}, {"radius", "length"}, {"size"}, {}};
  const std::vector<std::string> kShapeNames = {"sphere", "capsule", "cylinder", "box",
                                                "half_space"};
  for (const std::string key : {"radius", "length", "size"}) {
    const auto& keys = kShapeKeys[type];
    const bool takes = std::find(keys.begin(), keys.end(), key) != keys.end();
    if (g.Has(key) && !takes) {
      reader_.Fail(g.Get(key), g.Path(key),
                   "not used by shape " + kShapeNames[type] + "; expected " +
                       (keys.empty() ? std::string("no size keys") : JoinNames(keys)));
    }
    if (!g.Has(key) && takes) {
      reader_.Fail(g.node(), g.Path(key), "missing (required by shape " + kShapeNames[type] + ")");
    }
  }
  Shape shape;
  switch (type) {
    case 0:
      shape = Sphere{reader_.Positive(g.Get("radius"), g.Path("radius"))};
      break;
    case 1:
      shape = Capsule{reader_.Positive(g.Get("radius"), g.Path("radius")),
                      reader_.NonNegative(g.Get("length"), g.Path("length"))};
      break;
    case 2:
      shape = Cylinder{reader_.Positive(g.Get("radius"), g.Path("radius")),
                       reader_.Positive(g.Get("length"), g.Path("length"))};
      break;
    case 3: {
      const Eigen::Vector3d size = reader_.Vector3(g.Get("size"), g.Path("size"));
      for (int i = 0; i < 3; ++i) {
        if (!(size(i) > 0.0)) {
          reader_.FailValue(g.Get("size")[i], At(g.Path("size"), i), FormatValue(size(i)),
                            "a finite positive number (full side length, m)");
        }
      }
      shape = Box{size};
      break;
    }
    default:
      shape = HalfSpace{};
      break;
  }
  std::optional<InscribedSpheresOptions> inscribed_spheres;
  if (g.Has("inscribed_spheres")) {
    if (type != 3) {
      reader_.Fail(g.Get("inscribed_spheres"), g.Path("inscribed_spheres"),
                   "not used by shape " + kShapeNames[type] + "; expected only with shape: box");
    }
    inscribed_spheres =
        ReadInscribedSpheres(reader_, g.Get("inscribed_spheres"), g.Path("inscribed_spheres"));
  }
  const Eigen::Isometry3d X_BG = ReadPose(reader_, g);
  const std::string body_name = g.String("body", "world");
  if (!builder->HasBody(body_name)) {
    reader_.Fail(g.Get("body"), g.Path("body"),
                 "unknown body '" + body_name + "'; expected 'world' or a body of the models");
  }
  try {
    const BodyIndex body = builder->GetBodyIndex(body_name);
    if (!inscribed_spheres.has_value()) {
      builder->AddGeometry(name, body, X_BG, shape);
    } else {
      // The box's inscribed spheres instead of the box: <name>_sphere0, <name>_sphere1, ...
      const std::vector<InscribedSphere> spheres =
          InscribedSpheres(std::get<Box>(shape), *inscribed_spheres);
      for (std::size_t k = 0; k < spheres.size(); ++k) {
        builder->AddGeometry(name + "_sphere" + std::to_string(k), body,
                             X_BG * spheres[k].X_BoxSphere, spheres[k].sphere);
      }
    }
  } catch (const std::exception& e) {
    reader_.Fail(g.node(), g.path(), e.what());
  }
}

}  // namespace idto::config_internal
