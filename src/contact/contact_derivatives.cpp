#include "idto/contact/contact_derivatives.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>
#include <unsupported/Eigen/AutoDiff>

#include "idto/geometry/analytic_distance-inl.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "idto/multibody/algorithms/rnea_derivatives-inl.hpp"

namespace idto {

// The dual number of the pair geometry: value and derivatives along the six components of B's
// world twist (theta, rho).
using Dual6 = Eigen::AutoDiffScalar<Eigen::Matrix<double, 6, 1>>;
template bool AnalyticSignedDistance<Dual6>(const Shape&, const RigidTransformTpl<Dual6>&,
                                            const Shape&, const RigidTransformTpl<Dual6>&,
                                            SignedDistanceResultTpl<Dual6>*);

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Row12 = Eigen::Matrix<double, 1, 12>;
using Mat3x12 = Eigen::Matrix<double, 3, 12>;
using Mat6x24 = Eigen::Matrix<double, 6, 24>;

// Central-difference step of FCL pairs (rad, m): FCL's answers carry errors of about 1e-10 m,
// so a smaller step would amplify them (error ~ 1e-10 / step); truncation is ~ step^2.
constexpr double kFclStep = 1e-4;

// d(phi, n, p_WA, p_WB) / d(eps_A, eps_B), eps = (theta, rho) a world twist of each body.
// invariant: only B's columns (the last 6) are filled, and A's follow from the invariance under a
// common rigid motion eps of both bodies (phi does not change, n turns: dn = theta x n, and the
// witnesses move: dp = theta x p + rho), which PairForceJacobian applies at the level of the
// force; normal and p_C (the witnesses' midpoint) are the values it needs. Otherwise all 12.
struct PairGeometryJacobian {
  Row12 phi;
  Mat3x12 n, p_A, p_B;
  bool invariant{false};
  Vector3d normal, p_C;
};

RigidTransform GeometryPose(const Model& model, const Data& rnea, const GeometryInstance& g) {
  const BodyIndex m = model.mobilized_body(g.body);
  return rnea.X_WB_[m] * model.X_MB(g.body) * RigidTransform(g.X_BG.linear(), g.X_BG.translation());
}

// The origin of GeometryPose, with the same arithmetic (X_WM * t_MG).
Vector3d GeometryPosition(const Model& model, const Data& rnea, const GeometryInstance& g) {
  const BodyIndex m = model.mobilized_body(g.body);
  const Vector3d t = g.X_BG.translation();
  return (rnea.X_WB_[m] * model.X_MB(g.body)) * t;
}

// Marks J as invariant (B's columns filled) with the values at the pose.
void SetInvariant(const Vector3d& n, const Vector3d& p_A, const Vector3d& p_B,
                  PairGeometryJacobian* J) {
  J->invariant = true;
  J->normal = n;
  J->p_C = 0.5 * (p_A + p_B);
}

// Exact, through the templated pair code on Dual6 (B perturbed by its twist).
void AnalyticGeometryJacobian(const Shape& a, const RigidTransform& X_WGa, const Shape& b,
                              const RigidTransform& X_WGb, PairGeometryJacobian* J) {
  const RigidTransformTpl<Dual6> Xa = X_WGa.cast<Dual6>();
  Vector3<Dual6> theta, rho;
  for (int i = 0; i < 3; ++i) {
    theta(i) = Dual6(0.0, Eigen::Matrix<double, 6, 1>::Unit(i));
    rho(i) = Dual6(0.0, Eigen::Matrix<double, 6, 1>::Unit(i + 3));
  }
  RigidTransformTpl<Dual6> Xb = X_WGb.cast<Dual6>();
  for (int c = 0; c < 3; ++c) Xb.R.col(c) += theta.cross(Vector3<Dual6>(Xb.R.col(c)));
  Xb.p += theta.cross(Xb.p) + rho;
  SignedDistanceResultTpl<Dual6> r;
  AnalyticSignedDistance<Dual6>(a, Xa, b, Xb, &r);
  J->phi.tail<6>() = r.distance.derivatives().transpose();
  Vector3d n, p_A, p_B;
  for (int i = 0; i < 3; ++i) {
    J->n.block<1, 6>(i, 6) = r.normal_W(i).derivatives().transpose();
    J->p_A.block<1, 6>(i, 6) = r.p_WA(i).derivatives().transpose();
    J->p_B.block<1, 6>(i, 6) = r.p_WB(i).derivatives().transpose();
    n(i) = r.normal_W(i).value();
    p_A(i) = r.p_WA(i).value();
    p_B(i) = r.p_WB(i).value();
  }
  SetInvariant(n, p_A, p_B, J);
}

// Closed forms of the sphere pairs (sphere-sphere, and half-space-sphere: the engine puts a
// half-space first; every pair of the examples' models), the same quantities as the
// dual-number route above without its arithmetic on 7-component numbers (measured: 23 % of a
// bi-manual iteration went to that route). B's twist moves a point c of B by -[c]x theta + rho.
Eigen::Matrix<double, 3, 6> PointJacobian(const Vector3d& c) {
  Eigen::Matrix<double, 3, 6> J;
  J << -Skew<double>(c), Matrix3d::Identity();
  return J;
}

// Sphere-sphere, from the centres c_A, c_B (world) and the radii.
void SpherePairJacobian(const Vector3d& c_A, double r_A, const Vector3d& c_B, double r_B,
                        PairGeometryJacobian* J) {
  // d = c_B - c_A, phi = |d| - r_A - r_B, n = d / |d|, p_A = c_A + r_A n, p_B = c_B - r_B n.
  const SignedDistanceResultTpl<double> r =
      internal::SpherePair<double>(c_A, r_A, c_B, r_B, Vector3d::UnitZ());
  const Eigen::Matrix<double, 3, 6> Jc = PointJacobian(c_B);
  const double d2 = (c_B - c_A).squaredNorm();
  if (!(d2 > internal::kMinSquaredNorm)) {
    // Coincident centres: the fallback normal +z is fixed in the world, not carried by a
    // common motion of both bodies, so A's columns are direct: phi = (c_B - c_A) . z - r,
    // p_A = c_A + r_A z, p_B = c_B - r_B z.
    const Eigen::Matrix<double, 3, 6> Jc_A = PointJacobian(c_A);
    J->phi << -r.normal_W.transpose() * Jc_A, r.normal_W.transpose() * Jc;
    J->n.setZero();
    J->p_A << Jc_A, Eigen::Matrix<double, 3, 6>::Zero();
    J->p_B << Eigen::Matrix<double, 3, 6>::Zero(), Jc;
    J->invariant = false;
    return;
  }
  const Vector3d& n = r.normal_W;
  const Eigen::Matrix<double, 3, 6> Jn =
      ((Matrix3d::Identity() - n * n.transpose()) / std::sqrt(d2)) * Jc;
  J->phi.tail<6>() = n.transpose() * Jc;
  J->n.rightCols<6>() = Jn;
  J->p_A.rightCols<6>() = r_A * Jn;
  J->p_B.rightCols<6>() = Jc - r_B * Jn;
  SetInvariant(n, r.p_WA, r.p_WB, J);
}

// Half-space A, sphere B; false for other pairs, which take the dual-number route.
bool HalfSpaceSphereJacobian(const Shape& a, const RigidTransform& X_WGa, const Shape& b,
                             const RigidTransform& X_WGb, PairGeometryJacobian* J) {
  const Sphere* sb = std::get_if<Sphere>(&b);
  if (sb != nullptr && std::holds_alternative<HalfSpace>(a)) {
    // A the plane (normal m fixed), B the sphere (centre c moving): p = c - r m, h = m . (p -
    // p_A); flipped: n = m, p_A = p - h m (on the plane), p_B = p.
    SignedDistanceResultTpl<double> r;
    if (!AnalyticSignedDistance<double>(a, X_WGa, b, X_WGb, &r)) return false;
    const Vector3d m = X_WGa.R.col(2);
    const Eigen::Matrix<double, 3, 6> Jc = PointJacobian(X_WGb.p);
    J->phi.tail<6>() = m.transpose() * Jc;
    J->n.rightCols<6>().setZero();
    J->p_B.rightCols<6>() = Jc;
    J->p_A.rightCols<6>() = Jc - m * J->phi.tail<6>();
    SetInvariant(r.normal_W, r.p_WA, r.p_WB, J);
    return true;
  }
  return false;
}

// FCL pairs: central differences of SignedDistance over B's twist, rotations taken about B's
// geometry origin (then moved to the world origin).
void FclGeometryJacobian(const Shape& a, const RigidTransform& X_WGa, const Shape& b,
                         const RigidTransform& X_WGb, PairGeometryJacobian* J) {
  Eigen::Isometry3d Xa = Eigen::Isometry3d::Identity(), Xb = Eigen::Isometry3d::Identity();
  Xa.linear() = X_WGa.R;
  Xa.translation() = X_WGa.p;
  Eigen::Matrix<double, 10, 6> D;  // rows: phi, n, p_A, p_B; columns: local theta, rho
  for (int i = 0; i < 6; ++i) {
    const double h = kFclStep;
    Eigen::Matrix<double, 10, 1> y[2];
    for (int side = 0; side < 2; ++side) {
      const double step = side == 0 ? h : -h;
      Xb.linear() = X_WGb.R;
      Xb.translation() = X_WGb.p;
      if (i < 3) {
        Xb.linear() = Eigen::AngleAxisd(step, Vector3d::Unit(i)).toRotationMatrix() * X_WGb.R;
      } else {
        Xb.translation() += step * Vector3d::Unit(i - 3);
      }
      const SignedDistanceResult r = SignedDistance(a, Xa, b, Xb);
      y[side] << r.distance, r.normal_W, r.p_WA, r.p_WB;
    }
    D.col(i) = (y[0] - y[1]) / (2.0 * h);
  }
  // A world twist (theta, rho) is the rotation theta about B's origin p plus the translation
  // rho + theta x p.
  D.leftCols<3>() -= D.rightCols<3>() * Skew<double>(X_WGb.p);
  J->phi.tail<6>() = D.row(0);
  J->n.rightCols<6>() = D.middleRows<3>(1);
  J->p_A.rightCols<6>() = D.middleRows<3>(4);
  J->p_B.rightCols<6>() = D.middleRows<3>(7);
  const SignedDistanceResult r0 = SignedDistance(a, Xa, b, [&] {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = X_WGb.R;
    X.translation() = X_WGb.p;
    return X;
  }());
  SetInvariant(r0.normal_W, r0.p_WA, r0.p_WB, J);
}

// d F / d(eps_A, eps_B, V_A, V_B) (6 x 24) for F = (p_C x f, f), the force on B at the world
// origin. With v_c = v_B - v_A + (w_B - w_A) x p_C, v_n = n . v_c, v_t = v_c - v_n n and
// f = fn(phi, v_n) n + ft(phi, v_n, v_t):
//   df = a dphi + E dn + K dv_c,  a = dfn/dphi n + dft/dphi,  b = dfn/dv_n n + dft/dv_n,
//   K = b n^T + dft/dv_t (I - n n^T),  E = fn I + b v_c^T - dft/dv_t (n v_c^T + v_n I),
// where dv_c = [w_B - w_A]x dp_C along the poses and [[p_C]x, -I, -[p_C]x, I] along the
// velocities; dm = -[f]x dp_C + [p_C]x df.
void PairForceJacobian(const ContactResult& r, const PairGeometryJacobian& G,
                       const SpatialMotion& V_A, const SpatialMotion& V_B, Mat6x24* D) {
  const Vector3d& n = r.normal_W;
  const Vector3d& p = r.p_WC;
  const ContactForce& F = r.force;
  const Vector3d v_c = r.vn * n + r.vt;
  const Vector3d a = F.dfn_dphi * n + F.dft_dphi;
  const Vector3d b = F.dfn_dvn * n + F.dft_dvn;
  Matrix3d K = b * n.transpose() + F.dft_dvt;
  K.noalias() -= (F.dft_dvt * n) * n.transpose();
  Matrix3d E = F.fn * Matrix3d::Identity() + b * v_c.transpose() - r.vn * F.dft_dvt;
  E.noalias() -= (F.dft_dvt * n) * v_c.transpose();
  const Matrix3d P = Skew<double>(p);
  const Matrix3d Fx = Skew<double>(F.f);
  const Matrix3d KW = K * Skew<double>(Vector3d(V_B.w - V_A.w));
  // Poses: B's 6 columns, df = a dphi + E dn + KW dp_C, dm = [p]x df - [f]x dp_C.
  const Eigen::Matrix<double, 3, 6> Dp_B = 0.5 * (G.p_A.rightCols<6>() + G.p_B.rightCols<6>());
  Eigen::Matrix<double, 3, 6> Df_B = a * G.phi.tail<6>();
  Df_B.noalias() += E * G.n.rightCols<6>();
  Df_B.noalias() += KW * Dp_B;
  Eigen::Matrix<double, 3, 6> FDp_B;
  FDp_B.noalias() = Fx * Dp_B;
  D->block<3, 6>(3, 6) = Df_B;
  D->block<3, 6>(0, 6).noalias() = P * Df_B;
  D->block<3, 6>(0, 6) -= FDp_B;
  if (G.invariant) {
    // A's columns: G_A = G_rigid - G_B with dn_rigid = [-[n]x, 0] and dp_rigid = [-[p]x, I], so
    // Df_A = -Df_B + [-E [n]x - KW [p]x, KW] and dm_A = [p]x Df_A + [f]x Dp_B - [f]x dp_rigid.
    Eigen::Matrix<double, 3, 6> Df_A = -Df_B;
    Df_A.leftCols<3>().noalias() -= E * Skew<double>(G.normal);
    Df_A.leftCols<3>().noalias() -= KW * Skew<double>(G.p_C);
    Df_A.rightCols<3>() += KW;
    D->block<3, 6>(3, 0) = Df_A;
    D->block<3, 6>(0, 0).noalias() = P * Df_A;
    D->block<3, 6>(0, 0) += FDp_B;
    D->block<3, 3>(0, 0).noalias() += Fx * Skew<double>(G.p_C);
    D->block<3, 3>(0, 3) -= Fx;
  } else {
    const Eigen::Matrix<double, 3, 6> Dp_A = 0.5 * (G.p_A.leftCols<6>() + G.p_B.leftCols<6>());
    Eigen::Matrix<double, 3, 6> Df_A = a * G.phi.head<6>();
    Df_A.noalias() += E * G.n.leftCols<6>();
    Df_A.noalias() += KW * Dp_A;
    D->block<3, 6>(3, 0) = Df_A;
    D->block<3, 6>(0, 0).noalias() = P * Df_A;
    D->block<3, 6>(0, 0).noalias() -= Fx * Dp_A;
  }
  // Velocities (12 columns): df/dV_A = [K [p]x, -K], df/dV_B = -df/dV_A; dm = [p]x df.
  const Matrix3d KP = K * P;
  const Matrix3d PK = P * K;
  const Matrix3d PKP = PK * P;
  D->block<3, 3>(3, 12) = KP;
  D->block<3, 3>(3, 15) = -K;
  D->block<3, 3>(3, 18) = -KP;
  D->block<3, 3>(3, 21) = K;
  D->block<3, 3>(0, 12) = PKP;
  D->block<3, 3>(0, 15) = -PK;
  D->block<3, 3>(0, 18) = -PKP;
  D->block<3, 3>(0, 21) = PK;
}

// The velocity columns of the joints from the root to moving body m (none for the world).
void CollectChain(const Model& model, BodyIndex m, std::vector<int>* chain) {
  chain->clear();
  for (BodyIndex b = m; b != kWorldBody; b = model.moving_parent(b)) {
    const int iv = model.velocity_start(b);
    for (int c = 0; c < model.joint_nv(b); ++c) chain->push_back(iv + c);
  }
}

SpatialMotion Column(const Eigen::Matrix<double, 6, Eigen::Dynamic>& M, int k) {
  return {M.col(k).head<3>(), M.col(k).tail<3>()};
}

// J (world twists per column of the chain) and dV/dq = s x V + u of a body with velocity V.
void ChainJacobians(const Data& rnea, const std::vector<int>& chain, const SpatialMotion& V,
                    Eigen::Matrix<double, 6, Eigen::Dynamic>* J,
                    Eigen::Matrix<double, 6, Eigen::Dynamic>* dV) {
  for (int k : chain) {
    J->col(k) = rnea.S_.col(k);
    const SpatialMotion d = Cross(Column(rnea.S_, k), V) + Column(rnea.dV_dq_, k);
    dV->col(k) << d.w, d.v;
  }
}

// The pair's contribution through dF (the moment arm and the force change), rows of the
// joints that carry B but not A (minus) or A but not B (plus).
void AddPairTerms(const Mat6x24& D, ContactDerivativeWorkspace* ws, const Data& rnea,
                  Eigen::MatrixXd* dtau_dx, Eigen::MatrixXd* dtau_dv) {
  for (int k : ws->chain_union) {
    Eigen::Matrix<double, 6, 1> fx = Eigen::Matrix<double, 6, 1>::Zero(), fv = fx;
    if (ws->in_A[k]) {
      fx.noalias() += D.block<6, 6>(0, 0) * ws->J_A.col(k) + D.block<6, 6>(0, 12) * ws->dV_A.col(k);
      fv.noalias() += D.block<6, 6>(0, 12) * ws->J_A.col(k);
    }
    if (ws->in_B[k]) {
      fx.noalias() += D.block<6, 6>(0, 6) * ws->J_B.col(k) + D.block<6, 6>(0, 18) * ws->dV_B.col(k);
      fv.noalias() += D.block<6, 6>(0, 18) * ws->J_B.col(k);
    }
    ws->dF_dx.col(k) = fx;
    ws->dF_dv.col(k) = fv;
  }
  for (int j : ws->chain_union) {
    if (ws->in_A[j] == ws->in_B[j]) continue;  // common ancestors: +F and -F cancel
    const double sign = ws->in_B[j] ? -1.0 : 1.0;
    const auto s_j = rnea.S_.col(j);
    for (int k : ws->chain_union) {
      (*dtau_dx)(j, k) += sign * s_j.dot(ws->dF_dx.col(k));
      (*dtau_dv)(j, k) += sign * s_j.dot(ws->dF_dv.col(k));
    }
  }
}

// The derivative of J^T itself: d S_j / d x_k = s_k x S_j for the columns k of strict ancestor
// joints and the mixed-frame translations of j's own joint, against the subtree force.
void AddMotionSubspaceTerms(const Model& model, const Data& rnea, ContactDerivativeWorkspace* ws,
                            Eigen::MatrixXd* dtau_dx) {
  const std::vector<BodyIndex>& moving = model.moving_bodies();
  for (auto it = moving.rbegin(); it != moving.rend(); ++it) {
    const BodyIndex p = model.moving_parent(*it);
    if (p != kWorldBody) ws->F_net.col(p) += ws->F_net.col(*it);
  }
  for (BodyIndex b : moving) {
    const auto Fc = ws->F_net.col(b);
    if (Fc.isZero(0.0)) continue;
    const SpatialForce F(Fc.head<3>(), Fc.tail<3>());
    const int iv = model.velocity_start(b);
    const JointType type = model.joint_type(b);
    for (int r = 0; r < model.joint_nv(b); ++r) {
      const SpatialMotion S_j = Column(rnea.S_, iv + r);
      for (int c = 0; c < model.joint_nv(b); ++c) {
        if (!internal::IsMixedFrameTranslation(type, c)) continue;
        (*dtau_dx)(iv + r, iv + c) -= Dot(Cross(Column(rnea.S_, iv + c), S_j), F);
      }
      for (BodyIndex a = model.moving_parent(b); a != kWorldBody; a = model.moving_parent(a)) {
        const int av = model.velocity_start(a);
        for (int c = 0; c < model.joint_nv(a); ++c) {
          (*dtau_dx)(iv + r, av + c) -= Dot(Cross(Column(rnea.S_, av + c), S_j), F);
        }
      }
    }
  }
}

}  // namespace

ContactDerivativeWorkspace MakeContactDerivativeWorkspace(const Model& model,
                                                          const ContactEngine& engine) {
  const int nv = model.nv();
  ContactDerivativeWorkspace ws;
  for (auto* M : {&ws.J_A, &ws.J_B, &ws.dV_A, &ws.dV_B, &ws.dF_dx, &ws.dF_dv}) {
    M->setZero(6, nv);
  }
  ws.F_net.setZero(6, model.num_bodies());
  ws.chain_A.reserve(nv);
  ws.chain_B.reserve(nv);
  ws.chain_union.reserve(nv);
  ws.body_pairs.reserve(engine.num_pairs());
  ws.body_pair_D.reserve(engine.num_pairs());
  ws.in_A.assign(nv, 0);
  ws.in_B.assign(nv, 0);
  return ws;
}

ContactDerivativeStats AddContactDerivatives(const Model& model, const ContactEngine& engine,
                                             const ContactData& contact, const Data& rnea,
                                             ContactDerivativeWorkspace* ws,
                                             Eigen::MatrixXd* dtau_dq_tangent,
                                             Eigen::MatrixXd* dtau_dv) {
  ContactDerivativeStats stats;
  ws->F_net.setZero();
  ws->body_pairs.clear();
  ws->body_pair_D.clear();
  const std::vector<GeometryInstance>& geos = model.geometries();
  for (int c = 0; c < contact.num_active; ++c) {
    const ContactResult& r = contact.results[c];
    const ContactPair& pair = engine.pairs()[r.pair];
    const GeometryInstance& ga = geos[pair.geometry_a];
    const GeometryInstance& gb = geos[pair.geometry_b];
    PairGeometryJacobian G;
    const Sphere* sphere_a = std::get_if<Sphere>(&ga.shape);
    const Sphere* sphere_b = std::get_if<Sphere>(&gb.shape);
    if (r.exact && sphere_a != nullptr && sphere_b != nullptr) {
      // Only the centres (the poses' origins, without their rotations).
      SpherePairJacobian(GeometryPosition(model, rnea, ga), sphere_a->radius,
                         GeometryPosition(model, rnea, gb), sphere_b->radius, &G);
    } else if (r.exact) {
      const RigidTransform X_WGa = GeometryPose(model, rnea, ga);
      const RigidTransform X_WGb = GeometryPose(model, rnea, gb);
      if (!HalfSpaceSphereJacobian(ga.shape, X_WGa, gb.shape, X_WGb, &G)) {
        AnalyticGeometryJacobian(ga.shape, X_WGa, gb.shape, X_WGb, &G);
      }
    } else {
      FclGeometryJacobian(ga.shape, GeometryPose(model, rnea, ga), gb.shape,
                          GeometryPose(model, rnea, gb), &G);
      ++stats.num_fcl_pairs;
    }
    ++stats.num_pairs;
    const BodyIndex m_A = model.mobilized_body(pair.body_a);
    const BodyIndex m_B = model.mobilized_body(pair.body_b);
    const SpatialMotion V_A = m_A == kWorldBody ? SpatialMotion() : rnea.deriv_body_[m_A].V;
    const SpatialMotion V_B = m_B == kWorldBody ? SpatialMotion() : rnea.deriv_body_[m_B].V;
    Mat6x24 D;
    PairForceJacobian(r, G, V_A, V_B, &D);
    // Pairs between the same two bodies share the chain rule below: sum their D first.
    size_t e = 0;
    while (e < ws->body_pairs.size() && ws->body_pairs[e] != std::make_pair(m_A, m_B)) ++e;
    if (e == ws->body_pairs.size()) {
      ws->body_pairs.emplace_back(m_A, m_B);
      ws->body_pair_D.push_back(D);
    } else {
      ws->body_pair_D[e] += D;
    }
    const Eigen::Matrix<double, 6, 1> F0 =
        (Eigen::Matrix<double, 6, 1>() << r.p_WC.cross(r.force.f), r.force.f).finished();
    if (m_B != kWorldBody) ws->F_net.col(m_B) += F0;
    if (m_A != kWorldBody) ws->F_net.col(m_A) -= F0;
  }
  for (size_t e = 0; e < ws->body_pairs.size(); ++e) {
    const auto [m_A, m_B] = ws->body_pairs[e];
    CollectChain(model, m_A, &ws->chain_A);
    CollectChain(model, m_B, &ws->chain_B);
    const SpatialMotion V_A = m_A == kWorldBody ? SpatialMotion() : rnea.deriv_body_[m_A].V;
    const SpatialMotion V_B = m_B == kWorldBody ? SpatialMotion() : rnea.deriv_body_[m_B].V;
    ChainJacobians(rnea, ws->chain_A, V_A, &ws->J_A, &ws->dV_A);
    ChainJacobians(rnea, ws->chain_B, V_B, &ws->J_B, &ws->dV_B);
    ws->chain_union.clear();
    for (int k : ws->chain_A) ws->in_A[k] = 1;
    for (int k : ws->chain_B) ws->in_B[k] = 1;
    for (int k : ws->chain_A) ws->chain_union.push_back(k);
    for (int k : ws->chain_B) {
      if (!ws->in_A[k]) ws->chain_union.push_back(k);
    }
    AddPairTerms(ws->body_pair_D[e], ws, rnea, dtau_dq_tangent, dtau_dv);
    for (int k : ws->chain_union) ws->in_A[k] = ws->in_B[k] = 0;
  }
  AddMotionSubspaceTerms(model, rnea, ws, dtau_dq_tangent);
  return stats;
}

void SubtractBodyForceTorques(const Model& model, const BodyForces& F_ext, const Data& rnea,
                              Eigen::Matrix<double, 6, Eigen::Dynamic>* F_subtree,
                              Eigen::VectorXd* tau) {
  if (F_subtree->cols() != model.num_bodies()) F_subtree->resize(6, model.num_bodies());
  F_subtree->setZero();
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const BodyIndex m = model.mobilized_body(b);
    if (m == kWorldBody) continue;
    const auto F = F_ext.col(b);
    if (F.isZero(0.0)) continue;
    // The moment about the world origin: n + p_Bo x f.
    const Vector3d f = F.tail<3>();
    F_subtree->col(m).head<3>() += F.head<3>() + rnea.X_WB_[b].p.cross(f);
    F_subtree->col(m).tail<3>() += f;
  }
  const std::vector<BodyIndex>& moving = model.moving_bodies();
  for (auto it = moving.rbegin(); it != moving.rend(); ++it) {
    const BodyIndex p = model.moving_parent(*it);
    if (p != kWorldBody) F_subtree->col(p) += F_subtree->col(*it);
  }
  for (BodyIndex b : moving) {
    const int iv = model.velocity_start(b);
    for (int c = 0; c < model.joint_nv(b); ++c) {
      (*tau)(iv + c) -= rnea.S_.col(iv + c).dot(F_subtree->col(b));
    }
  }
}

}  // namespace idto
