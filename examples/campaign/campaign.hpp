#pragma once

// idto-campaign: an example's closed loop run many times under randomized conditions, each run
// reproducible from its seed (docs/mpc.md, "Campaigns"). This header: the conditions of a
// campaign, the draw of one run's conditions from its seed, and one run.

#include <cstdint>
#include <string>
#include <vector>

#include "idto/config/config.hpp"
#include "idto/multibody/model.hpp"
#include "run/metrics.hpp"

namespace idto::campaign {

/// The randomized conditions of a campaign (the "hard" defaults: DefaultSettings).
struct CampaignSettings {
  std::string example;        ///< example name (examples/NAME/NAME.yaml)
  std::string push_body;      ///< the body pushed (the example's main free body)
  bool push_along_x{false};   ///< planar systems in the x-z plane: push forward or backward only
  double max_impulse{0.0};    ///< N s: the push's impulse is uniform in [0, max_impulse]
  double push_duration{0.2};  ///< s: force = impulse / push_duration
  /// Plant mismatch: friction scaled by one factor and each body's mass and rotational inertia
  /// by its own factor, all uniform in [1 - mismatch, 1 + mismatch].
  double mismatch{0.3};
  double noise_position{1e-3};        ///< rad or m, per coordinate (mpc::SensorNoise::position)
  double noise_velocity{0.02};        ///< relative (mpc::SensorNoise::velocity_relative)
  double noise_velocity_floor{1e-3};  ///< rad/s or m/s (mpc::SensorNoise::velocity_floor)
  double latency{0.0};                ///< s: fixed latency base of every re-plan (reproducible)
  double jitter{0.0};                 ///< s: plus uniform [0, jitter] per re-plan
  /// Initial-state perturbation: Gaussian, standard deviation per coordinate, on the 1-DoF
  /// joints' positions (rad or m; base coordinates untouched, so nothing starts in the ground)
  /// and on every velocity (rad/s or m/s).
  double initial_position{1e-3};
  double initial_velocity{0.05};
  int threads{1};  ///< solver threads of the controller
  /// Solver iterations per control step (mpc.iterations_per_step); 0: the example's file.
  int iterations_per_step{0};
};

/// The hard defaults for `example` (spinner, quadruped, quadruped_hills, hopper, bimanual_lift,
/// allegro): pushes of up to 0.5 N s on the spinner's finger (its spinner turns about a fixed
/// axis through its origin, where a force has no moment), 8 N s on the quadruped's body, 0.5 N s
/// on the hopper's body, 6 N s on the bi-manual box, 0.05 N s on the Allegro ball, each over
/// 0.2 s; mismatch 30%; noise 1 mrad / 1 mm and 2%; a fixed latency about the example's mean
/// one-thread solve time and a jitter of twice that. Throws InvalidArgument naming the example
/// and the supported ones otherwise.
CampaignSettings DefaultSettings(const std::string& example);

/// The names DefaultSettings accepts.
std::vector<std::string> CampaignExamples();

/// What one run drew from its seed.
struct RunConditions {
  std::uint64_t seed{0};
  double push_time{0.0};       ///< s
  double push_direction{0.0};  ///< rad, in the horizontal plane from +x
  double push_impulse{0.0};    ///< N s
  double friction_scale{1.0};
  std::vector<double> mass_scale;  ///< per body (1 for the world and massless bodies)
  double total_mass_scale{1.0};    ///< plant's total mass / the controller's
  double initial_position_norm{0.0};
  double initial_velocity_norm{0.0};
};

/// The outcome of one run.
struct RunResult {
  int run_index{0};
  RunConditions conditions;
  bool success{false};
  /// "" on success, else what failed: "solver failure", "plant failure", or the failed parts of
  /// the task criterion joined by "+" (e.g. "tilt", "speed", "not reached").
  std::string failure_mode;
  std::string criterion;
  std::vector<examples::Metric> metrics;
  int num_replans{0};
  int rejected_plans{0};
  int late_plans{0};
  /// Control steps that started no re-plan: the solver was busy with a late one (an example
  /// whose `mpc.late_plans` is use_on_arrival; mpc::ClosedLoopLog::num_skipped_replans).
  int skipped_replans{0};
  int nonfinite_commands{0};
  std::string plant_failure;
  double plant_failure_time{-1.0};
};

/// Draws the conditions of the run with `seed` for `config`'s model (the order of the draws is
/// fixed; DrawConditions(..., s) is the same on every call).
RunConditions DrawConditions(const CampaignSettings& settings, const ExampleConfig& config,
                             std::uint64_t seed);

/// Runs the closed loop of `config` under the conditions drawn from `seed` against the MuJoCo
/// plant (a copy of the model with scaled masses and friction; the controller keeps the
/// nominal model) and judges it by the example's closed-loop task criterion. trajectory_csv:
/// when not null, receives the run's log (mpc::ClosedLoopLog::ToCsv: t, q, v, u and the contact
/// flags every `mpc.log_every` plant steps), to see how a run failed.
RunResult RunOne(const CampaignSettings& settings, const ExampleConfig& config, int run_index,
                 std::uint64_t seed, std::string* trajectory_csv = nullptr);

/// The failed parts of `task`'s criterion for `example` ("" when it succeeded).
std::string FailureMode(const std::string& example, const examples::TaskResult& task);

}  // namespace idto::campaign
