// Built against an installed idto by .ci/run: proves headers, library and CMake package work.
#include <idto/idto.hpp>

#include <iostream>

int main(int argc, char** argv) {
  std::cout << "idto " << IDTO_VERSION_STRING << " found\n";
  try {
    idto::CheckPositive("consumer", "dt", -1.0);
    std::cerr << "expected an exception\n";
    return 1;
  } catch (const idto::InvalidArgument& e) {
    std::cout << "errors work: " << e.what() << "\n";
  }
  (void)argc;
  (void)argv;
  return 0;
}
