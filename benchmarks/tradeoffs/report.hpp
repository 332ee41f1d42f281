#pragma once

/// @file
/// Output of idto-tradeoffs: Markdown text, number formatting, the machine description and
/// figures drawn by gnuplot.

#include <string>
#include <vector>

namespace idto::tradeoffs {

/// "6.1e-8" style: `digits` significant digits, exponent without padding; "–" for NaN.
std::string Sci(double x, int digits = 2);
/// Plain decimal with `digits` significant digits ("0.153", "12.4", "1530"); "–" for NaN.
std::string Num(double x, int digits = 3);
/// Shortest form of a parameter value ("%g": "0.001", "2e+08" as "2e8").
std::string G(double x);
/// A ratio "3.2×".
std::string Times(double x);
/// Milliseconds from seconds, 3 significant digits.
std::string Ms(double seconds);

/// A Markdown table built row by row.
class Table {
 public:
  explicit Table(std::vector<std::string> header) : header_(std::move(header)) {}
  void Row(std::vector<std::string> cells) { rows_.push_back(std::move(cells)); }
  std::string Markdown() const;

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

/// One section of tradeoffs.md, written by a study.
struct Section {
  std::string markdown;  ///< everything below the section's own heading
};

/// A finding a study reports to the summary: what a knob buys and what it costs.
struct Finding {
  std::string knob;      ///< the cheaper setting, e.g. "2 threads instead of 1"
  std::string example;   ///< where it was measured
  double speedup{1.0};   ///< time of the accurate setting / time of the cheaper one
  std::string speed;     ///< the speed measure in words with numbers
  std::string accuracy;  ///< the measured accuracy given up, in words with numbers
  /// True when the measured answer did not change beyond the stated threshold.
  bool free{false};
};

/// The machine, compiler and moment of a run, read when called.
struct MachineInfo {
  int cores{0};            ///< online processors this process may use (as nproc)
  std::string cpu;         ///< /proc/cpuinfo "model name"
  std::string compiler;    ///< the compiler of this program (and of the library with it)
  std::string build_type;  ///< CMake build type
  std::string date;        ///< UTC date and time
  std::string loadavg;     ///< first three fields of /proc/loadavg
  std::string kernel;      ///< uname -sr
  std::string omp_wait_policy;
};
MachineInfo ReadMachineInfo();
/// The 1-minute load average only (for the end-of-run record).
std::string ReadLoadAverage();

/// Writes `text` to `path` (throws on failure).
void WriteFile(const std::string& path, const std::string& text);

/// True when a `gnuplot` program is on the PATH.
bool HaveGnuplot();

/// Runs a gnuplot script (written to <data_dir>/<name>.gp) that writes `png_path`. Returns false
/// and prints a warning when gnuplot fails.
bool RunGnuplot(const std::string& data_dir, const std::string& name, const std::string& script);

/// The gnuplot preamble of every figure: pngcairo of the given size, output file, title.
std::string GnuplotHeader(const std::string& png_path, int width, int height);

/// Quotes a string for a gnuplot double-quoted literal.
std::string GnuplotQuote(const std::string& text);

}  // namespace idto::tradeoffs
