#pragma once

// What the example programs' command lines share (idto-run, idto-campaign): the exit codes, the
// usage error, and main()'s sequence of parse, help, run and error report.

#include <exception>
#include <iostream>
#include <string>

namespace idto::examples {

inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 1;
inline constexpr int kExitUsage = 2;

/// Thrown by an argument parser for bad command-line arguments (exit code kExitUsage).
struct UsageError {
  std::string message;
};

/// The body of a program's main(): `parse(argc, argv)` returns the Arguments (which have a
/// `help` flag) or throws UsageError, printed as "<program>: <message>" with the usage
/// (kExitUsage); --help prints the usage (kExitOk); otherwise `run(arguments)` gives the exit
/// code, and an exception from it is printed as "<program>: error: <what>" (kExitError).
template <typename Arguments, typename Parse, typename Run>
int RunCommandLine(const char* program, const char* usage, int argc, char** argv,
                   const Parse& parse, const Run& run) {
  Arguments args;
  try {
    args = parse(argc, argv);
  } catch (const UsageError& e) {
    std::cerr << program << ": " << e.message << "\n\n" << usage;
    return kExitUsage;
  }
  if (args.help) {
    std::cout << usage;
    return kExitOk;
  }
  try {
    return run(args);
  } catch (const std::exception& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return kExitError;
  }
}

}  // namespace idto::examples
