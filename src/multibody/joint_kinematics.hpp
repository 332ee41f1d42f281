#pragma once

// Moved to the installed, templated header (kept so existing includes keep working).
#include "idto/multibody/algorithms/joint_kinematics.hpp"
