// Heavy (ctest label "heavy"): the spinner, quadruped (flat and hills) and hopper campaigns of
// docs/mpc.md ("Campaigns"), 50 runs each with the default hard conditions and seed 1, in
// process. The runs are reproducible, so the counts are those of the table; the thresholds below
// sit under them so that a regression of the controller (or of the campaign's conditions) fails
// here.

#include <gtest/gtest.h>

#include <iostream>
#include <string>
#include <vector>

#include "campaign/campaign.hpp"
#include "campaign/campaign_report.hpp"
#include "idto/config/config.hpp"
#include "idto/sim/plant.hpp"

namespace idto {
namespace {

int CampaignSuccesses(const std::string& name, int runs, std::uint64_t seed) {
  const std::vector<std::string> share_dirs = {IDTO_SOURCE_DIR};
  const ExampleConfig config = LoadExampleConfig(FindExampleConfig(name, share_dirs), share_dirs);
  const campaign::CampaignSettings settings = campaign::DefaultSettings(name);
  std::vector<campaign::RunResult> results;
  int successes = 0;
  for (int i = 0; i < runs; ++i) {
    results.push_back(campaign::RunOne(settings, config, i, seed + i));
    successes += results.back().success ? 1 : 0;
    EXPECT_EQ(results.back().nonfinite_commands, 0) << name << " run " << i;
  }
  std::cout << campaign::CampaignMarkdown(settings, results);
  return successes;
}

TEST(CampaignHeavy, Spinner50Runs) {
  if (!sim::HaveMujoco()) GTEST_SKIP() << "idto was built without MuJoCo";
  // docs/mpc.md: 48 of 50 at this seed with session 10's controller (2 rad/s target), 49 of 50
  // at session 25's build; 26 of 50 before that controller.
  EXPECT_GE(CampaignSuccesses("spinner", 50, 1), 45);
}

TEST(CampaignHeavy, Quadruped50Runs) {
  if (!sim::HaveMujoco()) GTEST_SKIP() << "idto was built without MuJoCo";
  // docs/mpc.md: 50 of 50 at this seed with session 19's flat controller (planner smoothing
  // 2 mm; 591 of 600 on seeds 5001-16001), 48 of 50 on the hills (session 19: ground 2 mm); 50
  // of 50 with session 36's flat controller (Lagrange multipliers).
  EXPECT_GE(CampaignSuccesses("quadruped", 50, 1), 48);
}

TEST(CampaignHeavy, QuadrupedHills50Runs) {
  if (!sim::HaveMujoco()) GTEST_SKIP() << "idto was built without MuJoCo";
  // docs/mpc.md: 49 of 50 at this seed with session 29's controller (the planner's friction 1.3
  // on the hills, a 25 ms grid) and the elliptic-cone plant; 45 with session 21's controller,
  // which this threshold would fail, and 50 with that controller and the pyramidal cone; 50 with
  // session 36's (Lagrange multipliers with the constraint correction).
  EXPECT_GE(CampaignSuccesses("quadruped_hills", 50, 1), 47);
}

TEST(CampaignHeavy, Hopper50Runs) {
  if (!sim::HaveMujoco()) GTEST_SKIP() << "idto was built without MuJoCo";
  // docs/mpc.md: 46 of 50 at this seed with session 26's controller (a goal 0.7 m from the
  // start, a 30 % heavier shin in the planner's model) and the elliptic-cone plant (session 28);
  // 40 with the pyramidal cone, which this threshold would fail.
  EXPECT_GE(CampaignSuccesses("hopper", 50, 1), 44);
}

}  // namespace
}  // namespace idto
