// "Model only what a scene requires": geometry the task never touches must not change what the
// solver computes. The quadruped example (examples/quadruped/quadruped.yaml) is solved as
// configured and with 100 extra geometries, as in benchmarks/scene_bench.cpp: 50 static spheres
// 3-5.5 m away (real contact pairs, removed only by pruning, through the static broad phase)
// and 50 spheres on the robot's bodies whose pairs are excluded. Costs and iterates must be
// bitwise equal: pruning may skip work, never change results.

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "idto/idto.hpp"

namespace idto {
namespace {

ExampleConfig LoadQuadruped() {
  const std::vector<std::string> dirs{IDTO_SOURCE_DIR};
  return LoadExampleConfig(FindExampleConfig("quadruped", dirs), dirs);
}

// The scene re-created with a ModelBuilder (its URDF models, then its own geometry), plus the
// clutter appended, so the plain scene's pairs keep their geometry indices and relative order.
ExampleConfig AddClutter(const ExampleConfig& plain) {
  ModelBuilder builder(plain.model.name());
  for (const SceneModelConfig& m : plain.models) AddUrdfFile(m.urdf_file, m.options, &builder);
  const std::vector<GeometryInstance>& scene = plain.model.geometries();
  const size_t from_urdf = builder.Build().geometries().size();
  for (size_t g = from_urdf; g < scene.size(); ++g) {
    builder.AddGeometry(scene[g].name, scene[g].body, scene[g].X_BG, scene[g].shape);
  }
  builder.SetGravity(plain.model.gravity());
  ExampleConfig cluttered = plain;
  ContactOptions& contact = cluttered.problem.contact;
  for (int i = 0; i < 50; ++i) {
    const std::string name = "clutter_static" + std::to_string(i);
    const double angle = 2.0 * M_PI * i / 50.0, distance = 3.0 + 0.05 * i;
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() << distance * std::cos(angle), distance * std::sin(angle), 0.2 + 0.02 * i;
    builder.AddGeometry(name, kWorldBody, X, Sphere{0.05 + 0.005 * i});
    if (!contact.included_pairs.empty()) contact.included_pairs.emplace_back(name, "*");
  }
  for (int i = 0; i < 50; ++i) {
    const std::string name = "clutter_body" + std::to_string(i);
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() << 0.01 * (i % 5), 0.01 * ((i / 5) % 5), 0.01 * (i / 25);
    builder.AddGeometry(name, 1 + i % (plain.model.num_bodies() - 1), X, Sphere{0.01});
    contact.excluded_pairs.emplace_back(name, "*");
  }
  cluttered.model = builder.Build();
  return cluttered;
}

TEST(SolverClutter, ClutterTheTaskNeverTouchesChangesNothing) {
  const ExampleConfig plain = LoadQuadruped();
  const ExampleConfig cluttered = AddClutter(plain);
  ASSERT_EQ(cluttered.model.geometries().size(), plain.model.geometries().size() + 100);
  const ContactEngine plain_engine(plain.model, plain.problem.contact);
  const ContactEngine cluttered_engine(cluttered.model, cluttered.problem.contact);
  // The static spheres are real pairs with every robot geometry; the body spheres are not.
  EXPECT_EQ(cluttered_engine.num_pairs(), plain_engine.num_pairs() + 50 * 8);

  for (int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    std::vector<SolverSummary> summaries;
    std::vector<Trajectory> solutions(2);
    for (int c = 0; c < 2; ++c) {
      const ExampleConfig& config = c == 0 ? plain : cluttered;
      SolverOptions o = config.solver;
      o.max_iterations = 4;
      o.fixed_iterations = true;
      o.num_threads = threads;
      TrajectoryOptimizer opt(config.model, config.problem, o);
      summaries.push_back(opt.Solve(MakeInitialGuess(config), &solutions[c]));
      // A warm start continues from the same iterate and radius.
      opt.mutable_options().max_iterations = 2;
      const SolverSummary more = opt.SolveWarmStart(&solutions[c]);
      summaries.back().log.insert(summaries.back().log.end(), more.log.begin(), more.log.end());
      summaries.back().final_cost = more.final_cost;
    }
    const SolverSummary& a = summaries[0];
    const SolverSummary& b = summaries[1];
    ASSERT_EQ(a.log.size(), 6u) << a.message;
    ASSERT_EQ(b.log.size(), a.log.size()) << b.message;
    EXPECT_EQ(a.initial_cost, b.initial_cost);
    EXPECT_EQ(a.final_cost, b.final_cost);
    for (size_t i = 0; i < a.log.size(); ++i) {
      EXPECT_EQ(a.log[i].cost, b.log[i].cost) << "iteration " << i;
      EXPECT_EQ(a.log[i].trial_cost, b.log[i].trial_cost) << "iteration " << i;
      EXPECT_EQ(a.log[i].gradient_norm, b.log[i].gradient_norm) << "iteration " << i;
      EXPECT_EQ(a.log[i].accepted, b.log[i].accepted) << "iteration " << i;
    }
    ASSERT_EQ(solutions[0].q.size(), solutions[1].q.size());
    for (size_t k = 0; k < solutions[0].q.size(); ++k) {
      EXPECT_TRUE(solutions[0].q[k] == solutions[1].q[k]) << "q_" << k << " differs";
      EXPECT_TRUE(solutions[0].tau[k] == solutions[1].tau[k]) << "tau_" << k << " differs";
    }
  }
}

}  // namespace
}  // namespace idto
