#include "convert.hpp"

#include <sstream>

#include <pythread.h>

namespace idto::python {

namespace {

std::string ShapeOf(const py::array& a) {
  std::ostringstream s;
  s << "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s << (i ? ", " : "") << a.shape(i);
  if (a.ndim() == 1) s << ",";
  s << ")";
  return s.str();
}

std::string Dim(Eigen::Index n, const char* any) { return n < 0 ? any : std::to_string(n); }

std::string Described(const std::string& shape, const char* shape_name) {
  return shape_name ? shape + " (" + shape_name + ")" : shape;
}

/// obj as a C-contiguous float64 array; throws unless it holds real numbers.
py::array_t<double> AsDoubles(py::handle obj, const char* where, const char* name,
                              const std::string& expected) {
  py::array raw = py::array::ensure(obj);
  if (!raw) {
    const std::string type = py::str(py::type::handle_of(obj).attr("__name__"));
    ThrowInvalidArgument(where, name, "a " + type + " that is not an array", expected);
  }
  const char kind = raw.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    const std::string dtype = py::str(raw.dtype());
    ThrowInvalidArgument(where, name, "an array of dtype " + dtype + " and shape " + ShapeOf(raw),
                         expected + " of real numbers (float64)");
  }
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(raw);
}

}  // namespace

Eigen::VectorXd ToVector(py::handle obj, const char* where, const char* name, Eigen::Index size,
                         const char* size_name) {
  const std::string expected = Described("shape (" + Dim(size, "n") + ",)", size_name);
  const py::array_t<double> a = AsDoubles(obj, where, name, "an array of " + expected);
  if (a.ndim() != 1 || (size >= 0 && a.shape(0) != size)) {
    ThrowInvalidArgument(where, name, "an array of shape " + ShapeOf(a), expected);
  }
  return Eigen::Map<const Eigen::VectorXd>(a.data(), a.shape(0));
}

Eigen::MatrixXd ToMatrix(py::handle obj, const char* where, const char* name, Eigen::Index rows,
                         Eigen::Index cols, const char* shape_name) {
  const std::string expected =
      Described("shape (" + Dim(rows, "m") + ", " + Dim(cols, "n") + ")", shape_name);
  const py::array_t<double> a = AsDoubles(obj, where, name, "an array of " + expected);
  if (a.ndim() != 2 || (rows >= 0 && a.shape(0) != rows) || (cols >= 0 && a.shape(1) != cols)) {
    ThrowInvalidArgument(where, name, "an array of shape " + ShapeOf(a), expected);
  }
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(a.data(), a.shape(0), a.shape(1));
}

std::vector<Eigen::VectorXd> ToVectors(py::handle obj, const char* where, const char* name,
                                       Eigen::Index rows, Eigen::Index cols,
                                       const char* shape_name) {
  const Eigen::MatrixXd m = ToMatrix(obj, where, name, rows, cols, shape_name);
  std::vector<Eigen::VectorXd> out(static_cast<size_t>(m.rows()));
  for (Eigen::Index k = 0; k < m.rows(); ++k) out[static_cast<size_t>(k)] = m.row(k).transpose();
  return out;
}

Eigen::Isometry3d ToIsometry(py::handle obj, const char* where, const char* name) {
  const Eigen::Matrix4d m = ToMatrix(obj, where, name, 4, 4, "a homogeneous transform");
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  const bool bottom_ok = m.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1), 0.0);
  const bool rotation_ok = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-9 &&
                           R.determinant() > 0.0 && m.allFinite();
  if (!bottom_ok || !rotation_ok) {
    ThrowInvalidArgument(where, name, "not a rigid transform",
                         "a 4 x 4 matrix [R p; 0 0 0 1] with R a rotation");
  }
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R;
  X.translation() = m.topRightCorner<3, 1>();
  return X;
}

py::array_t<double> ToArray(const Eigen::VectorXd& x) {
  py::array_t<double> a(x.size());
  std::copy(x.data(), x.data() + x.size(), a.mutable_data());
  return a;
}

py::array_t<double> ToArray(const std::vector<double>& x) {
  py::array_t<double> a(static_cast<py::ssize_t>(x.size()));
  std::copy(x.begin(), x.end(), a.mutable_data());
  return a;
}

py::array_t<double> ToArray(const std::vector<Eigen::VectorXd>& x) {
  const py::ssize_t rows = static_cast<py::ssize_t>(x.size());
  const py::ssize_t cols = x.empty() ? 0 : x.front().size();
  py::array_t<double> a({rows, cols});
  double* out = a.mutable_data();
  for (const Eigen::VectorXd& row : x) {
    if (row.size() != cols) throw std::runtime_error("idto: rows of different sizes");
    std::copy(row.data(), row.data() + cols, out);
    out += cols;
  }
  return a;
}

py::array_t<double> ToArray(const Eigen::MatrixXd& x) {
  py::array_t<double> a({static_cast<py::ssize_t>(x.rows()), static_cast<py::ssize_t>(x.cols())});
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Eigen::Map<RowMajor>(a.mutable_data(), x.rows(), x.cols()) = x;
  return a;
}

void CheckIndex(const char* where, const char* name, long index, long size) {
  if (index < 0 || index >= size) {
    std::ostringstream s;
    s << where << ": " << name << " is " << index << "; expected an index in [0, " << size << ")";
    throw py::index_error(s.str());
  }
}

// ---- Pending errors ----

namespace {
struct PendingError {
  PyObject* type{nullptr};
  PyObject* value{nullptr};
  PyObject* traceback{nullptr};
};
thread_local PendingError pending;
unsigned long main_thread_ident = 0;
}  // namespace

void StorePendingError() {
  ClearPendingError();
  PyErr_Fetch(&pending.type, &pending.value, &pending.traceback);
}

bool HasPendingError() { return pending.type != nullptr; }

void RaisePendingError() {
  if (!HasPendingError()) return;
  PyErr_Restore(pending.type, pending.value, pending.traceback);
  pending = PendingError{};
  throw py::error_already_set();
}

void ClearPendingError() {
  Py_XDECREF(pending.type);
  Py_XDECREF(pending.value);
  Py_XDECREF(pending.traceback);
  pending = PendingError{};
}

void RecordMainThread() {
  main_thread_ident =
      py::module_::import("threading").attr("main_thread")().attr("ident").cast<unsigned long>();
}

bool OnMainThread() { return PyThread_get_thread_ident() == main_thread_ident; }

}  // namespace idto::python
