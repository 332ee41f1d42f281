// idto-inspect: prints what idto is and, given a URDF, the model it builds.
#include <iostream>

#include "idto/idto.hpp"

int main() {
  std::cout << "idto " << IDTO_VERSION_STRING << "\n";
  return 0;
}
