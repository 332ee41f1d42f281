#pragma once

/// @file
/// Point and frame Jacobians (need ForwardKinematics first).

#include <Eigen/Core>

#include "idto/multibody/data.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// J (3 x nv, resized): world-aligned translational Jacobian of point C fixed in body b at p_BC:
/// v_WC = J v. Any body, welded ones included; body 0 gives zeros.
void CalcPointJacobian(const Model& model, const Data& data, BodyIndex b,
                       const Eigen::Vector3d& p_BC, Eigen::Matrix3Xd* J);

/// J (6 x nv, resized): [angular; translational] world-aligned Jacobian of frame F fixed in body
/// b at X_BF (the translational rows are for the origin of F).
void CalcFrameJacobian(const Model& model, const Data& data, BodyIndex b,
                       const Eigen::Isometry3d& X_BF, Eigen::Matrix<double, 6, Eigen::Dynamic>* J);

}  // namespace idto
