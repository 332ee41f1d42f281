#include "idto/multibody/data-inl.hpp"

namespace idto {

template class DataTpl<double>;

}  // namespace idto
