#pragma once

// idto-campaign's results: the Wilson interval, the JSON of a campaign (settings, runs,
// summary), reading such files back to merge shards, and the Markdown table.

#include <string>
#include <vector>

#include "campaign/campaign.hpp"

namespace idto::campaign {

/// A confidence interval of a proportion.
struct Interval {
  double low{0.0};
  double high{1.0};
};

/// The Wilson score interval of `successes` in `n` trials (0 <= successes <= n) at the normal
/// quantile z (default 1.96: 95%): (p + z^2/2n -+ z sqrt(p(1-p)/n + z^2/4n^2)) / (1 + z^2/n)
/// with p = successes / n; [0, 1] for n = 0. Throws InvalidArgument on bad counts.
Interval WilsonInterval(int successes, int n, double z = 1.959963984540054);

/// The JSON of a campaign: {"settings": ..., "runs": [...], "summary": ...}, runs in the given
/// order; every number printed with 17 significant digits, so reading it back is exact. Holds
/// nothing machine-dependent (no wall-clock times): equal runs give equal text.
std::string CampaignJson(const CampaignSettings& settings, const std::vector<RunResult>& runs);

/// Reads a file written by CampaignJson (a whole campaign, a shard or a single run). Throws
/// std::runtime_error naming `file` and what is wrong.
void ReadCampaignJson(const std::string& text, const std::string& file, CampaignSettings* settings,
                      std::vector<RunResult>* runs);

/// Merges the runs of several files: the settings must agree, run indices must not repeat; the
/// runs are sorted by run index. Throws std::runtime_error naming the file otherwise.
void MergeCampaigns(const std::vector<std::string>& texts, const std::vector<std::string>& files,
                    CampaignSettings* settings, std::vector<RunResult>* runs);

/// The Markdown report: success rate with its 95% Wilson interval, failure modes, per-condition
/// breakdown (push impulse tercile, friction and mass below/above nominal, late re-plans, the
/// push's direction as the nearest horizontal axis, and the upper impulse tercile by direction)
/// and re-plan counts.
std::string CampaignMarkdown(const CampaignSettings& settings, const std::vector<RunResult>& runs);

}  // namespace idto::campaign
