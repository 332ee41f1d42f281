#include "campaign/campaign_report.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "idto/core/errors.hpp"
#include "run/json_text.hpp"

namespace idto::campaign {
namespace {

std::string Num(double x) {
  if (!std::isfinite(x)) return "null";
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", x);
  return buffer;
}

std::string Quote(const std::string& s) { return idto::examples::JsonQuote(s); }

std::string NumList(const std::vector<double>& xs) {
  std::string out = "[";
  for (size_t i = 0; i < xs.size(); ++i) out += (i ? ", " : "") + Num(xs[i]);
  return out + "]";
}

/// Counts of one group of runs.
struct Group {
  std::string name;
  int n{0};
  int successes{0};
};

struct Summary {
  int n{0};
  int successes{0};
  Interval interval;
  std::map<std::string, int> failure_modes;
  std::vector<Group> groups;
  long long replans{0}, late{0}, skipped{0}, rejected{0}, nonfinite{0};
  int runs_with_late{0};
};

// The push's direction as the nearest of the four horizontal axes: 0 +x, 1 +y, 2 -x, 3 -y
// (a direction exactly between two takes the one counter-clockwise from it); -1 when it is not
// finite (a file read with --merge may hold null).
int PushQuadrant(double direction) {
  if (!std::isfinite(direction)) return -1;
  const int q = static_cast<int>(std::floor(direction / (0.5 * M_PI) + 0.5));
  return ((q % 4) + 4) % 4;
}

constexpr const char* kQuadrantNames[] = {"+x", "+y", "-x", "-y"};

// The breakdown's groups, in the report's order: impulse terciles, friction, mass, late
// re-plans, then by push direction (the nearest horizontal axis; +-x only for pushes along x),
// and the upper impulse tercile by direction (where a system is weakest against large pushes,
// e.g. the Allegro ball pushed towards the wrist, docs/mpc.md).
std::vector<Group> MakeGroups(const CampaignSettings& settings) {
  std::vector<Group> groups = {
      {"push impulse in the lower third", 0, 0}, {"push impulse in the middle third", 0, 0},
      {"push impulse in the upper third", 0, 0}, {"friction below nominal", 0, 0},
      {"friction at or above nominal", 0, 0},    {"total mass below nominal", 0, 0},
      {"total mass at or above nominal", 0, 0},  {"no late re-plan", 0, 0},
      {"at least one late re-plan", 0, 0}};
  for (const char* prefix : {"push towards ", "push impulse in the upper third towards "}) {
    for (int q = 0; q < 4; ++q) {
      if (settings.push_along_x && q % 2 == 1) continue;
      groups.push_back({std::string(prefix) + kQuadrantNames[q], 0, 0});
    }
  }
  return groups;
}

Summary Summarize(const CampaignSettings& settings, const std::vector<RunResult>& runs) {
  Summary s;
  s.groups = MakeGroups(settings);
  // Pushes along x only have two directions: groups 9, 10 (+x, -x) and 11, 12 (upper third).
  const int directions = settings.push_along_x ? 2 : 4;
  for (const RunResult& r : runs) {
    ++s.n;
    s.successes += r.success ? 1 : 0;
    if (!r.success) ++s.failure_modes[r.failure_mode];
    const double fraction =
        settings.max_impulse > 0.0 ? r.conditions.push_impulse / settings.max_impulse : 0.0;
    const int tercile = std::clamp(static_cast<int>(std::floor(3.0 * fraction)), 0, 2);
    const int quadrant = PushQuadrant(r.conditions.push_direction);
    // Along x only: the sign of the push's x component (the draws are 0 or pi).
    const int direction = !settings.push_along_x                         ? quadrant
                          : std::cos(r.conditions.push_direction) >= 0.0 ? 0
                                                                         : 1;
    std::vector<int> in = {tercile, r.conditions.friction_scale < 1.0 ? 3 : 4,
                           r.conditions.total_mass_scale < 1.0 ? 5 : 6, r.late_plans > 0 ? 8 : 7};
    if (quadrant >= 0) {
      in.push_back(9 + direction);
      if (tercile == 2) in.push_back(9 + directions + direction);
    }
    for (int g : in) {
      ++s.groups[g].n;
      s.groups[g].successes += r.success ? 1 : 0;
    }
    s.replans += r.num_replans;
    s.late += r.late_plans;
    s.skipped += r.skipped_replans;
    s.rejected += r.rejected_plans;
    s.nonfinite += r.nonfinite_commands;
    s.runs_with_late += r.late_plans > 0 ? 1 : 0;
  }
  s.interval = WilsonInterval(s.successes, s.n);
  return s;
}

void WriteSettings(const CampaignSettings& s, std::ostream& out) {
  out << "  \"settings\": {\"example\": " << Quote(s.example)
      << ", \"push_body\": " << Quote(s.push_body)
      << ", \"push_along_x\": " << (s.push_along_x ? "true" : "false")
      << ", \"max_impulse_Ns\": " << Num(s.max_impulse)
      << ", \"push_duration_s\": " << Num(s.push_duration) << ", \"mismatch\": " << Num(s.mismatch)
      << ", \"noise_position\": " << Num(s.noise_position)
      << ", \"noise_velocity_relative\": " << Num(s.noise_velocity)
      << ", \"noise_velocity_floor\": " << Num(s.noise_velocity_floor)
      << ", \"latency_s\": " << Num(s.latency) << ", \"jitter_s\": " << Num(s.jitter)
      << ", \"initial_position\": " << Num(s.initial_position)
      << ", \"initial_velocity\": " << Num(s.initial_velocity) << ", \"threads\": " << s.threads
      << ", \"iterations_per_step\": " << s.iterations_per_step << "},\n";
}

void WriteRun(const RunResult& r, std::ostream& out) {
  const RunConditions& c = r.conditions;
  out << "    {\"run_index\": " << r.run_index << ", \"seed\": " << c.seed
      << ", \"success\": " << (r.success ? "true" : "false")
      << ", \"failure_mode\": " << Quote(r.failure_mode) << ",\n     \"conditions\": {"
      << "\"push_time_s\": " << Num(c.push_time)
      << ", \"push_direction_rad\": " << Num(c.push_direction)
      << ", \"push_impulse_Ns\": " << Num(c.push_impulse)
      << ", \"friction_scale\": " << Num(c.friction_scale)
      << ", \"total_mass_scale\": " << Num(c.total_mass_scale)
      << ", \"initial_position_norm\": " << Num(c.initial_position_norm)
      << ", \"initial_velocity_norm\": " << Num(c.initial_velocity_norm)
      << ", \"mass_scale\": " << NumList(c.mass_scale) << "},\n     \"replans\": " << r.num_replans
      << ", \"rejected_plans\": " << r.rejected_plans << ", \"late_plans\": " << r.late_plans
      << ", \"skipped_replans\": " << r.skipped_replans
      << ", \"nonfinite_commands\": " << r.nonfinite_commands
      << ", \"plant_failure\": " << Quote(r.plant_failure)
      << ", \"plant_failure_time_s\": " << Num(r.plant_failure_time)
      << ",\n     \"criterion\": " << Quote(r.criterion) << ",\n     \"metrics\": [";
  for (size_t i = 0; i < r.metrics.size(); ++i) {
    const examples::Metric& m = r.metrics[i];
    out << (i ? ", " : "") << "{\"name\": " << Quote(m.name)
        << ", \"values\": " << NumList(m.values)
        << ", \"array\": " << (m.is_array ? "true" : "false") << "}";
  }
  out << "]}";
}

void WriteSummary(const Summary& s, std::ostream& out) {
  out << "  \"summary\": {\"runs\": " << s.n << ", \"successes\": " << s.successes
      << ", \"success_rate\": " << Num(s.n > 0 ? static_cast<double>(s.successes) / s.n : 0.0)
      << ", \"wilson95_low\": " << Num(s.interval.low)
      << ", \"wilson95_high\": " << Num(s.interval.high) << ",\n    \"failure_modes\": {";
  bool first = true;
  for (const auto& [mode, count] : s.failure_modes) {
    out << (first ? "" : ", ") << Quote(mode) << ": " << count;
    first = false;
  }
  out << "},\n    \"breakdown\": [";
  for (size_t i = 0; i < s.groups.size(); ++i) {
    out << (i ? ",\n      " : "\n      ") << "{\"condition\": " << Quote(s.groups[i].name)
        << ", \"runs\": " << s.groups[i].n << ", \"successes\": " << s.groups[i].successes << "}";
  }
  out << "],\n    \"replans\": " << s.replans << ", \"late_plans\": " << s.late
      << ", \"runs_with_late_plans\": " << s.runs_with_late
      << ", \"skipped_replans\": " << s.skipped << ", \"rejected_plans\": " << s.rejected
      << ", \"nonfinite_commands\": " << s.nonfinite << "}\n";
}

// ------------------------------------------------------------------------------- reading

[[noreturn]] void Fail(const std::string& file, const std::string& what) {
  throw std::runtime_error(file + ": " + what);
}

YAML::Node Field(const YAML::Node& map, const std::string& key, const std::string& file,
                 const std::string& where) {
  if (!map.IsMap() || !map[key]) Fail(file, where + ": missing \"" + key + "\"");
  return map[key];
}

template <typename T>
T As(const YAML::Node& map, const std::string& key, const std::string& file,
     const std::string& where) {
  const YAML::Node node = Field(map, key, file, where);
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    Fail(file, where + "." + key + ": not a value of the expected type");
  }
}

double AsNumber(const YAML::Node& node) {
  if (node.IsNull()) return std::numeric_limits<double>::quiet_NaN();
  return node.as<double>();
}

double Number(const YAML::Node& map, const std::string& key, const std::string& file,
              const std::string& where) {
  const YAML::Node node = Field(map, key, file, where);
  try {
    return AsNumber(node);
  } catch (const YAML::Exception&) {
    Fail(file, where + "." + key + ": not a number");
  }
}

std::vector<double> Numbers(const YAML::Node& node, const std::string& file,
                            const std::string& where) {
  if (!node.IsSequence()) Fail(file, where + ": not a list of numbers");
  std::vector<double> xs;
  for (const YAML::Node& x : node) xs.push_back(AsNumber(x));
  return xs;
}

CampaignSettings ReadSettings(const YAML::Node& n, const std::string& file) {
  const std::string w = "settings";
  CampaignSettings s;
  s.example = As<std::string>(n, "example", file, w);
  s.push_body = As<std::string>(n, "push_body", file, w);
  s.push_along_x = As<bool>(n, "push_along_x", file, w);
  s.max_impulse = Number(n, "max_impulse_Ns", file, w);
  s.push_duration = Number(n, "push_duration_s", file, w);
  s.mismatch = Number(n, "mismatch", file, w);
  s.noise_position = Number(n, "noise_position", file, w);
  s.noise_velocity = Number(n, "noise_velocity_relative", file, w);
  s.noise_velocity_floor = Number(n, "noise_velocity_floor", file, w);
  s.latency = Number(n, "latency_s", file, w);
  s.jitter = Number(n, "jitter_s", file, w);
  s.initial_position = Number(n, "initial_position", file, w);
  s.initial_velocity = Number(n, "initial_velocity", file, w);
  s.threads = As<int>(n, "threads", file, w);
  // Absent in files written before the option existed: the example's own setting.
  if (n["iterations_per_step"]) s.iterations_per_step = As<int>(n, "iterations_per_step", file, w);
  return s;
}

RunResult ReadRun(const YAML::Node& n, const std::string& file, const std::string& w) {
  RunResult r;
  r.run_index = As<int>(n, "run_index", file, w);
  r.success = As<bool>(n, "success", file, w);
  r.failure_mode = As<std::string>(n, "failure_mode", file, w);
  const YAML::Node c = Field(n, "conditions", file, w);
  const std::string wc = w + ".conditions";
  RunConditions& k = r.conditions;
  k.seed = As<std::uint64_t>(n, "seed", file, w);
  k.push_time = Number(c, "push_time_s", file, wc);
  k.push_direction = Number(c, "push_direction_rad", file, wc);
  k.push_impulse = Number(c, "push_impulse_Ns", file, wc);
  k.friction_scale = Number(c, "friction_scale", file, wc);
  k.total_mass_scale = Number(c, "total_mass_scale", file, wc);
  k.initial_position_norm = Number(c, "initial_position_norm", file, wc);
  k.initial_velocity_norm = Number(c, "initial_velocity_norm", file, wc);
  k.mass_scale = Numbers(Field(c, "mass_scale", file, wc), file, wc + ".mass_scale");
  r.num_replans = As<int>(n, "replans", file, w);
  r.rejected_plans = As<int>(n, "rejected_plans", file, w);
  r.late_plans = As<int>(n, "late_plans", file, w);
  // Absent in files written before the key existed (every late plan then was discarded).
  r.skipped_replans = n["skipped_replans"] ? As<int>(n, "skipped_replans", file, w) : 0;
  r.nonfinite_commands = As<int>(n, "nonfinite_commands", file, w);
  r.plant_failure = As<std::string>(n, "plant_failure", file, w);
  r.plant_failure_time = Number(n, "plant_failure_time_s", file, w);
  r.criterion = As<std::string>(n, "criterion", file, w);
  const YAML::Node metrics = Field(n, "metrics", file, w);
  if (!metrics.IsSequence()) Fail(file, w + ".metrics: not a list");
  for (const YAML::Node& m : metrics) {
    examples::Metric metric;
    metric.name = As<std::string>(m, "name", file, w + ".metrics");
    metric.values = Numbers(Field(m, "values", file, w + ".metrics"), file, w + ".metrics");
    metric.is_array = As<bool>(m, "array", file, w + ".metrics");
    r.metrics.push_back(metric);
  }
  return r;
}

bool SameSettings(const CampaignSettings& a, const CampaignSettings& b) {
  return a.example == b.example && a.push_body == b.push_body && a.push_along_x == b.push_along_x &&
         a.max_impulse == b.max_impulse && a.push_duration == b.push_duration &&
         a.mismatch == b.mismatch && a.noise_position == b.noise_position &&
         a.noise_velocity == b.noise_velocity && a.noise_velocity_floor == b.noise_velocity_floor &&
         a.latency == b.latency && a.jitter == b.jitter &&
         a.initial_position == b.initial_position && a.initial_velocity == b.initial_velocity &&
         a.threads == b.threads && a.iterations_per_step == b.iterations_per_step;
}

std::string Percent(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.1f %%", 100.0 * x);
  return buffer;
}

}  // namespace

Interval WilsonInterval(int successes, int n, double z) {
  if (n < 0 || successes < 0 || successes > n) {
    ThrowInvalidArgument("WilsonInterval", "successes, n",
                         std::to_string(successes) + ", " + std::to_string(n),
                         "0 <= successes <= n");
  }
  CheckPositive("WilsonInterval", "z", z);
  if (n == 0) return {0.0, 1.0};
  const double nn = static_cast<double>(n);
  const double p = successes / nn;
  const double z2 = z * z;
  const double centre = p + z2 / (2.0 * nn);
  const double half = z * std::sqrt(p * (1.0 - p) / nn + z2 / (4.0 * nn * nn));
  const double denominator = 1.0 + z2 / nn;
  return {std::max(0.0, (centre - half) / denominator),
          std::min(1.0, (centre + half) / denominator)};
}

std::string CampaignJson(const CampaignSettings& settings, const std::vector<RunResult>& runs) {
  std::ostringstream out;
  out << "{\n";
  WriteSettings(settings, out);
  out << "  \"runs\": [";
  for (size_t i = 0; i < runs.size(); ++i) {
    out << (i ? ",\n" : "\n");
    WriteRun(runs[i], out);
  }
  out << "],\n";
  WriteSummary(Summarize(settings, runs), out);
  out << "}\n";
  return out.str();
}

void ReadCampaignJson(const std::string& text, const std::string& file, CampaignSettings* settings,
                      std::vector<RunResult>* runs) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    Fail(file, std::string("not valid JSON: ") + e.what());
  }
  if (!root.IsMap()) Fail(file, "expected a JSON object written by idto-campaign");
  *settings = ReadSettings(Field(root, "settings", file, "top level"), file);
  const YAML::Node list = Field(root, "runs", file, "top level");
  if (!list.IsSequence()) Fail(file, "runs: not a list");
  runs->clear();
  for (std::size_t i = 0; i < list.size(); ++i) {
    runs->push_back(ReadRun(list[i], file, "runs[" + std::to_string(i) + "]"));
  }
}

void MergeCampaigns(const std::vector<std::string>& texts, const std::vector<std::string>& files,
                    CampaignSettings* settings, std::vector<RunResult>* runs) {
  if (texts.empty()) throw std::runtime_error("idto-campaign --merge: no files to merge");
  runs->clear();
  std::map<int, std::string> seen;
  for (size_t f = 0; f < texts.size(); ++f) {
    CampaignSettings s;
    std::vector<RunResult> part;
    ReadCampaignJson(texts[f], files[f], &s, &part);
    if (f == 0) {
      *settings = s;
    } else if (!SameSettings(s, *settings)) {
      Fail(files[f], "its settings differ from those of " + files[0] + " (example '" + s.example +
                         "' against '" + settings->example + "')");
    }
    for (RunResult& r : part) {
      const auto [it, inserted] = seen.emplace(r.run_index, files[f]);
      if (!inserted) {
        Fail(files[f], "run " + std::to_string(r.run_index) + " is also in " + it->second);
      }
      runs->push_back(std::move(r));
    }
  }
  std::sort(runs->begin(), runs->end(),
            [](const RunResult& a, const RunResult& b) { return a.run_index < b.run_index; });
}

std::string CampaignMarkdown(const CampaignSettings& settings, const std::vector<RunResult>& runs) {
  const Summary s = Summarize(settings, runs);
  std::ostringstream out;
  out << "### " << settings.example << ": " << s.successes << " of " << s.n << " runs succeeded\n\n"
      << "Conditions: push on `" << settings.push_body << "` up to " << settings.max_impulse
      << " N s over " << settings.push_duration << " s, friction and masses within +-"
      << 100.0 * settings.mismatch << " %, noise " << settings.noise_position << " rad or m on q, "
      << 100.0 * settings.noise_velocity << " % (floor " << settings.noise_velocity_floor
      << ") on v, latency " << 1e3 * settings.latency << " ms + uniform [0, "
      << 1e3 * settings.jitter << "] ms, " << settings.threads << " solver thread(s)"
      << (settings.iterations_per_step > 0
              ? ", " + std::to_string(settings.iterations_per_step) + " iteration(s) per step"
              : std::string())
      << ".\n\n"
      << "| example | runs | successes | success rate | 95% Wilson interval | late re-plans "
         "(runs with any) | skipped re-plans (solver busy) | rejected re-plans | non-finite "
         "commands |\n"
      << "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n"
      << "| " << settings.example << " | " << s.n << " | " << s.successes << " | "
      << Percent(s.n > 0 ? static_cast<double>(s.successes) / s.n : 0.0) << " | "
      << Percent(s.interval.low) << " - " << Percent(s.interval.high) << " | " << s.late << " of "
      << s.replans << " (" << s.runs_with_late << ") | " << s.skipped << " | " << s.rejected
      << " | " << s.nonfinite << " |\n\n";
  out << "| failure mode | runs |\n| --- | --- |\n";
  if (s.failure_modes.empty()) out << "| (none) | 0 |\n";
  for (const auto& [mode, count] : s.failure_modes) out << "| " << mode << " | " << count << " |\n";
  out << "\n| condition | runs | successes | success rate |\n| --- | --- | --- | --- |\n";
  for (const Group& g : s.groups) {
    out << "| " << g.name << " | " << g.n << " | " << g.successes << " | "
        << (g.n > 0 ? Percent(static_cast<double>(g.successes) / g.n) : "-") << " |\n";
  }
  return out.str();
}

}  // namespace idto::campaign
