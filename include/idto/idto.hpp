#pragma once

/// @file
/// Umbrella header: everything a user of idto needs.

#include "idto/version.hpp"

// core
#include "idto/core/errors.hpp"
#include "idto/core/parallel.hpp"
#include "idto/core/types.hpp"
