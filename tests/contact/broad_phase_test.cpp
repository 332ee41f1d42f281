// Evaluate and EvaluateChanged over a crowd of static geometry: the static broad phase (reused
// from the reference's or the previous Evaluate while the moving geometry stays within its
// clearance, queried again beyond it) gives bitwise the results, order and forces of an
// Evaluate into a new ContactData.

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "idto/idto.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

// Two free balls and a hinged arm among 60 static spheres (a third welded to a fixed table).
Model Crowd() { return test::StaticCrowd(5, /*with_arm=*/true); }

void ExpectSame(const ContactEngine& engine, const ContactData& changed, const ContactData& fresh) {
  ASSERT_EQ(changed.num_active, fresh.num_active);
  EXPECT_EQ(changed.num_pruned, fresh.num_pruned);
  EXPECT_EQ(changed.num_active + changed.num_pruned, engine.num_pairs());
  for (int i = 0; i < fresh.num_active; ++i) {
    EXPECT_EQ(changed.results[i].pair, fresh.results[i].pair);
    EXPECT_EQ(changed.results[i].phi, fresh.results[i].phi);
    EXPECT_TRUE(changed.results[i].force.f == fresh.results[i].force.f);
  }
  EXPECT_TRUE(changed.F_ext == fresh.F_ext);
  for (int p = 0; p < engine.num_pairs(); ++p) {
    EXPECT_EQ(changed.result_of_pair[p] >= 0, fresh.result_of_pair[p] >= 0) << "pair " << p;
  }
}

TEST(ContactBroadPhase, EvaluateChangedMatchesEvaluateAmongStaticGeometry) {
  const Model model = Crowd();
  ContactOptions o;
  o.force_tolerance = 1e-3;
  o.parameters.smoothing = 0.02;
  const ContactEngine engine(model, o);
  ContactData reference = engine.MakeData(model), changed = engine.MakeData(model),
              fresh = engine.MakeData(model), chained = engine.MakeData(model);
  Data data(model);
  test::Random rng(11);
  const int ball1 = model.GetPositionStart("ball1_free");
  const int vball1 = model.GetVelocityStart("ball1_free");
  std::vector<char> moved(model.num_bodies(), 0);
  moved[model.GetBodyIndex("ball1")] = 1;
  int active_seen = 0;
  for (int trial = 0; trial < 60; ++trial) {
    Eigen::VectorXd q = model.NeutralConfiguration();
    q.segment<3>(ball1 + 4) = rng.Vector(3, -1.0, 1.0);
    q.segment<3>(model.GetPositionStart("ball2_free") + 4) = rng.Vector(3, -1.0, 1.0);
    q(model.GetPositionStart("shoulder")) = rng.Uniform(-1.5, 1.5);
    Eigen::VectorXd v = rng.Vector(model.nv());
    ForwardKinematics(model, q, v, &data);
    engine.Evaluate(model, data, &reference);
    ASSERT_NE(reference.broad_phase_owner, 0u);
    // Finite-difference sized moves (the reference's broad phase is reused), then moves of
    // up to a metre (queried again).
    for (double size : {1e-8, 1e-3, 0.1, 1.0}) {
      SCOPED_TRACE("trial " + std::to_string(trial) + ", move " + std::to_string(size));
      Eigen::VectorXd q2 = q, v2 = v;
      q2.segment<3>(ball1 + 4) += size * rng.Vector(3, -1.0, 1.0);
      q2.segment<4>(ball1) += size * rng.Vector(4, -1.0, 1.0);
      q2.segment<4>(ball1).normalize();
      v2.segment<6>(vball1) += rng.Vector(6);
      ForwardKinematics(model, q2, v2, &data);
      engine.EvaluateChanged(model, data, reference, moved, &changed);
      EXPECT_EQ(changed.broad_phase_owner, 0u);
      engine.Evaluate(model, data, &fresh);
      // `fresh` keeps its broad phase from the previous pose while it holds (temporal
      // coherence): the same answer as a ContactData without any record.
      ContactData clean = engine.MakeData(model);
      engine.Evaluate(model, data, &clean);
      ExpectSame(engine, fresh, clean);
      ExpectSame(engine, changed, fresh);
      active_seen += fresh.num_active;
      // A reference that is itself an EvaluateChanged result has no broad phase to reuse.
      engine.EvaluateChanged(model, data, changed, moved, &chained);
      ExpectSame(engine, chained, fresh);
    }
  }
  EXPECT_GT(active_seen, 100);
}

TEST(ContactBroadPhase, EvaluateChangedWithAMovedStaticBody) {
  // Flagging a static body (the welded table) re-queries every moving geometry; with the same
  // poses the answer is Evaluate's.
  const Model model = Crowd();
  ContactOptions o;
  o.force_tolerance = 1e-3;
  const ContactEngine engine(model, o);
  ContactData reference = engine.MakeData(model), changed = engine.MakeData(model);
  Data data(model);
  test::Random rng(13);
  std::vector<char> moved(model.num_bodies(), 0);
  moved[model.GetBodyIndex("table")] = 1;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd q = model.NeutralConfiguration();
    q.segment<3>(model.GetPositionStart("ball1_free") + 4) = rng.Vector(3, -1.0, 1.0);
    q.segment<3>(model.GetPositionStart("ball2_free") + 4) = rng.Vector(3, -1.0, 1.0);
    ForwardKinematics(model, q, rng.Vector(model.nv()), &data);
    engine.Evaluate(model, data, &reference);
    engine.EvaluateChanged(model, data, reference, moved, &changed);
    ExpectSame(engine, changed, reference);
  }
}

}  // namespace
}  // namespace idto
