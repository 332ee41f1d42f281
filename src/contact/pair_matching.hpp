#pragma once

// How the names of ContactOptions' filters and overrides match geometries, and which geometry
// pairs can touch at all (private to the library: ContactEngine and its option checks).

#include <string>

#include "idto/core/types.hpp"
#include "idto/multibody/model.hpp"

namespace idto::contact_internal {

/// True when `name` is "*", the name of geometry g or the name of its body.
bool NameMatches(const Model& model, const std::string& name, GeometryIndex g);

/// True when (a, b) matches the geometries (ga, gb) in either order.
bool PairMatches(const Model& model, const std::string& a, const std::string& b, GeometryIndex ga,
                 GeometryIndex gb);

/// True when geometries ga and gb can touch before any filter: on different rigid bodies (not
/// both on the world) and not two half-spaces.
bool CanTouch(const Model& model, GeometryIndex ga, GeometryIndex gb);

}  // namespace idto::contact_internal
