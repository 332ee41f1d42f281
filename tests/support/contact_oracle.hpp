#pragma once

// The oracle of the analytic contact derivatives: inverse dynamics with contact written out
// once more on Eigen's AutoDiffScalar (forward kinematics, the templated analytic pair code and
// contact law, the body forces, the templated RNEA), differentiated with respect to the raw q
// and v. Only the geometry and law kernels are shared with the library's contact engine; the
// velocity of the contact point, the body forces and every chain rule are this file's own.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include "idto/contact/contact_derivatives.hpp"
#include "idto/contact/contact_engine.hpp"
#include "idto/contact/contact_law-inl.hpp"
#include "idto/geometry/analytic_distance-inl.hpp"
#include "idto/multibody/algorithms/dynamics-inl.hpp"
#include "idto/multibody/algorithms/kinematics-inl.hpp"
#include "idto/multibody/algorithms/rnea_derivatives-inl.hpp"
#include "idto/multibody/data-inl.hpp"

namespace idto {
namespace test {

using ADX = Eigen::AutoDiffScalar<Eigen::VectorXd>;

struct TauDerivatives {
  Eigen::VectorXd tau;      // nv
  Eigen::MatrixXd dtau_dq;  // nv x nq (raw coordinates)
  Eigen::MatrixXd dtau_dv;  // nv x nv
  int num_pairs{0};         // pairs with a non-zero force (or all evaluated, analytic side)
};

// tau = ID(q, v, a) - sum J^T f over the pairs of `engine` listed in `pairs` (indices into
// engine.pairs(); every pair must be analytic; no engine: no contact), on AD scalars whose
// derivative vectors all have `n` entries (any seeding).
inline VectorX<ADX> TauWithContactAD(const Model& model, const ContactEngine* engine,
                                     const std::vector<int>& pairs, const VectorX<ADX>& q_ad,
                                     const VectorX<ADX>& v_ad, const VectorX<ADX>& a_ad, int n) {
  DataTpl<ADX> data(model);
  ForwardKinematics<ADX>(model, q_ad, v_ad, &data);
  BodyForcesTpl<ADX> F(6, model.num_bodies());
  for (int j = 0; j < F.cols(); ++j) {
    for (int i = 0; i < 6; ++i) F(i, j) = ADX(0.0, Eigen::VectorXd::Zero(n));
  }
  const std::vector<GeometryInstance>& geos = model.geometries();
  for (int i : pairs) {
    const ContactPair& pair = engine->pairs()[i];
    const GeometryInstance& ga = geos[pair.geometry_a];
    const GeometryInstance& gb = geos[pair.geometry_b];
    const RigidTransformTpl<ADX> X_WGa =
        data.pose(pair.body_a) *
        RigidTransform(ga.X_BG.linear(), ga.X_BG.translation()).cast<ADX>();
    const RigidTransformTpl<ADX> X_WGb =
        data.pose(pair.body_b) *
        RigidTransform(gb.X_BG.linear(), gb.X_BG.translation()).cast<ADX>();
    SignedDistanceResultTpl<ADX> sd;
    if (!AnalyticSignedDistance<ADX>(ga.shape, X_WGa, gb.shape, X_WGb, &sd)) {
      throw std::runtime_error("contact oracle: pair " + std::to_string(i) + " is not analytic");
    }
    const Vector3<ADX> p_C = ADX(0.5) * (sd.p_WA + sd.p_WB);
    const Vector3<ADX> r_B = p_C - data.pose(pair.body_b).p;
    const Vector3<ADX> r_A = p_C - data.pose(pair.body_a).p;
    const Vector3<ADX> v_c = (data.v_WBo(pair.body_b) + data.w_WB(pair.body_b).cross(r_B)) -
                             (data.v_WBo(pair.body_a) + data.w_WB(pair.body_a).cross(r_A));
    const ADX vn = sd.normal_W.dot(v_c);
    const Vector3<ADX> vt = v_c - vn * sd.normal_W;
    const ContactForceTpl<ADX> force =
        CalcContactForceTpl<ADX>(pair.parameters, sd.distance, vn, vt, sd.normal_W);
    F.col(pair.body_b).template head<3>() += r_B.cross(force.f);
    F.col(pair.body_b).template tail<3>() += force.f;
    F.col(pair.body_a).template head<3>() -= r_A.cross(force.f);
    F.col(pair.body_a).template tail<3>() -= force.f;
  }
  return InverseDynamicsAfterKinematics<ADX>(model, v_ad, a_ad, &F, &data);
}

// The same tau and its derivatives by forward-mode AD over (q, v).
inline TauDerivatives AutoDiffTauWithContact(const Model& model, const ContactEngine& engine,
                                             const std::vector<int>& pairs,
                                             const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                             const Eigen::VectorXd& a) {
  const int nq = model.nq(), nv = model.nv(), n = nq + nv;
  VectorX<ADX> q_ad(nq), v_ad(nv), a_ad(nv);
  for (int i = 0; i < nq; ++i) q_ad(i) = ADX(q(i), n, i);
  for (int i = 0; i < nv; ++i) v_ad(i) = ADX(v(i), n, nq + i);
  for (int i = 0; i < nv; ++i) a_ad(i) = ADX(a(i), Eigen::VectorXd::Zero(n));
  const VectorX<ADX> tau = TauWithContactAD(model, &engine, pairs, q_ad, v_ad, a_ad, n);
  TauDerivatives out;
  out.tau.resize(nv);
  Eigen::MatrixXd J(nv, n);
  for (int i = 0; i < nv; ++i) {
    out.tau(i) = tau(i).value();
    J.row(i) = tau(i).derivatives().size() == n ? Eigen::VectorXd(tau(i).derivatives())
                                                : Eigen::VectorXd::Zero(n);
  }
  out.dtau_dq = J.leftCols(nq);
  out.dtau_dv = J.rightCols(nv);
  out.num_pairs = static_cast<int>(pairs.size());
  return out;
}

// The library's analytic derivatives of the same tau: ComputeRneaDerivatives, the contact
// evaluation and AddContactDerivatives, in raw coordinates.
inline TauDerivatives AnalyticTauWithContact(const Model& model, const ContactEngine& engine,
                                             const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                             const Eigen::VectorXd& a,
                                             std::vector<int>* evaluated_pairs) {
  Data data(model);
  ContactData contact = engine.MakeData(model);
  ForwardKinematics(model, q, v, &data);
  engine.Evaluate(model, data, &contact);
  ComputeRneaDerivatives(model, q, v, a, nullptr, &data);
  ContactDerivativeWorkspace ws = MakeContactDerivativeWorkspace(model, engine);
  const ContactDerivativeStats stats = AddContactDerivatives(model, engine, contact, data, &ws,
                                                             &data.dtau_dq_tangent, &data.dtau_dv);
  internal::RneaDerivativesToRawCoordinates(model, q.data(), &data);
  Data ref(model);
  TauDerivatives out;
  out.tau = InverseDynamics(model, q, v, a, contact.F_ext, &ref);
  out.dtau_dq = data.dtau_dq;
  out.dtau_dv = data.dtau_dv;
  out.num_pairs = stats.num_pairs;
  evaluated_pairs->clear();
  for (int c = 0; c < contact.num_active; ++c) evaluated_pairs->push_back(contact.results[c].pair);
  return out;
}

}  // namespace test
}  // namespace idto
