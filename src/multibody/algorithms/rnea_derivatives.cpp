#include "idto/multibody/algorithms/rnea_derivatives-inl.hpp"

namespace idto {

template void ComputeRneaDerivatives<double>(const Model&, const ConstVectorRef<double>&,
                                             const ConstVectorRef<double>&,
                                             const ConstVectorRef<double>&,
                                             const BodyForcesTpl<double>*, DataTpl<double>*);

void ComputeRneaDerivatives(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                            const Eigen::Ref<const Eigen::VectorXd>& v,
                            const Eigen::Ref<const Eigen::VectorXd>& a, const BodyForces* F_ext,
                            Data* data) {
  ComputeRneaDerivatives<double>(model, q, v, a, F_ext, data);
}

void ComputeRneaDerivatives(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                            const Eigen::Ref<const Eigen::VectorXd>& v,
                            const Eigen::Ref<const Eigen::VectorXd>& a, Data* data) {
  ComputeRneaDerivatives<double>(model, q, v, a, nullptr, data);
}

void ComputeRneaDerivativesTangent(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                                   const Eigen::Ref<const Eigen::VectorXd>& v,
                                   const Eigen::Ref<const Eigen::VectorXd>& a,
                                   const BodyForces* F_ext, Data* data) {
  internal::ComputeRneaDerivativesTangent<double>(model, q, v, a, F_ext, data);
}

}  // namespace idto
