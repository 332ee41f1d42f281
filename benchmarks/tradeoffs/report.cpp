#include "report.hpp"

#include <sched.h>
#include <sys/utsname.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace idto::tradeoffs {

std::string Sci(double x, int digits) {
  if (std::isnan(x)) return "–";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  if (x == 0.0) return "0";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*e", std::max(0, digits - 1), x);
  std::string s = buffer;
  const size_t e = s.find('e');
  std::string mantissa = s.substr(0, e);
  std::string exponent = s.substr(e + 1);
  const bool negative = exponent[0] == '-';
  size_t first = 1;
  while (first + 1 < exponent.size() && exponent[first] == '0') ++first;
  exponent = (negative ? "-" : "") + exponent.substr(first);
  if (exponent == "0") return mantissa;
  return mantissa + "e" + exponent;
}

std::string Num(double x, int digits) {
  if (std::isnan(x)) return "–";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  if (x == 0.0) return "0";
  const double magnitude = std::floor(std::log10(std::abs(x)));
  if (magnitude < -3 || magnitude >= 7) return Sci(x, digits);
  const int decimals = std::max(0, digits - 1 - static_cast<int>(magnitude));
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, x);
  return buffer;
}

std::string G(double x) {
  char buffer[64];
  if (x != 0.0 && (std::abs(x) >= 1e4 || std::abs(x) < 1e-3)) {
    // 1e4, 2.5e-5: mantissa without trailing zeros, exponent without padding.
    std::snprintf(buffer, sizeof(buffer), "%.3e", x);
    std::string s = buffer;
    const size_t e = s.find('e');
    std::string mantissa = s.substr(0, e);
    while (mantissa.back() == '0') mantissa.pop_back();
    if (mantissa.back() == '.') mantissa.pop_back();
    const int exponent = std::atoi(s.c_str() + e + 1);
    return mantissa + "e" + std::to_string(exponent);
  }
  std::snprintf(buffer, sizeof(buffer), "%g", x);
  return buffer;
}

std::string Times(double x) { return Num(x, 2) + "×"; }

std::string Ms(double seconds) { return Num(1e3 * seconds, 3); }

std::string Table::Markdown() const {
  std::ostringstream out;
  const auto line = [&](const std::vector<std::string>& cells) {
    out << '|';
    for (const std::string& c : cells) out << ' ' << c << " |";
    out << '\n';
  };
  line(header_);
  out << '|';
  for (size_t i = 0; i < header_.size(); ++i) out << " --- |";
  out << '\n';
  for (const auto& row : rows_) line(row);
  return out.str();
}

namespace {

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\n");
  const size_t b = s.find_last_not_of(" \t\n");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

std::string CompilerName() {
#if defined(__clang__)
  return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("g++ ") + __VERSION__;
#else
  return "unknown compiler";
#endif
}

}  // namespace

std::string ReadLoadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  if (!(in >> one >> five >> fifteen)) return "unknown";
  return one + " " + five + " " + fifteen;
}

MachineInfo ReadMachineInfo() {
  MachineInfo info;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0) info.cores = CPU_COUNT(&set);
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) info.cpu = Trim(line.substr(colon + 1));
      break;
    }
  }
  if (info.cpu.empty()) info.cpu = "unknown CPU";
  info.compiler = CompilerName();
#ifdef IDTO_TRADEOFFS_BUILD_TYPE
  info.build_type = IDTO_TRADEOFFS_BUILD_TYPE;
#endif
  if (info.build_type.empty()) info.build_type = "unknown build type";
  char date[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof(date), "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  info.date = date;
  info.loadavg = ReadLoadAverage();
  struct utsname name;
  if (uname(&name) == 0) info.kernel = std::string(name.sysname) + " " + name.release;
  const char* wait = std::getenv("OMP_WAIT_POLICY");
  info.omp_wait_policy = wait != nullptr ? wait : "unset";
  return info;
}

void WriteFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

bool HaveGnuplot() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

bool RunGnuplot(const std::string& data_dir, const std::string& name, const std::string& script) {
  const std::string path = data_dir + "/" + name + ".gp";
  WriteFile(path, script);
  const std::string command = "gnuplot '" + path + "' 2>'" + data_dir + "/" + name + ".log'";
  if (std::system(command.c_str()) != 0) {
    std::cerr << "idto-tradeoffs: warning: gnuplot failed on " << path << " (see " << data_dir
              << "/" << name << ".log); figure skipped\n";
    return false;
  }
  return true;
}

std::string GnuplotHeader(const std::string& png_path, int width, int height) {
  std::ostringstream out;
  out << "set terminal pngcairo size " << width << "," << height << " font \"DejaVu Sans,11\"\n"
      << "set output " << GnuplotQuote(png_path) << "\n"
      << "set datafile separator \",\"\n"
      << "set grid\n";
  return out.str();
}

std::string GnuplotQuote(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace idto::tradeoffs
