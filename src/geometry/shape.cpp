#include "idto/geometry/shape.hpp"

namespace idto {

std::string ShapeName(const Shape& shape) {
  struct Namer {
    std::string operator()(const Sphere&) const { return "sphere"; }
    std::string operator()(const Capsule&) const { return "capsule"; }
    std::string operator()(const Cylinder&) const { return "cylinder"; }
    std::string operator()(const Box&) const { return "box"; }
    std::string operator()(const HalfSpace&) const { return "half_space"; }
  };
  return std::visit(Namer{}, shape);
}

}  // namespace idto
