#pragma once

// Conversions between numpy arrays and Eigen / std::vector<Eigen::VectorXd>, with checks that
// raise ValueError naming the argument and the expected shape; the bind_* registration
// functions; the pending-Python-error slot used by solver callbacks.

#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <Eigen/Core>

#include <idto/idto.hpp>

namespace idto::python {

namespace py = pybind11;

/// A vector argument: a 1-D array (or sequence) of real numbers; `size` >= 0 checks its length
/// (`size_name` explains it in the message, e.g. "nq"). Throws InvalidArgument (ValueError)
/// naming `where` and `name`.
Eigen::VectorXd ToVector(py::handle obj, const char* where, const char* name,
                         Eigen::Index size = -1, const char* size_name = nullptr);

/// A matrix argument of shape (rows, cols) (-1: any).
Eigen::MatrixXd ToMatrix(py::handle obj, const char* where, const char* name, Eigen::Index rows,
                         Eigen::Index cols, const char* shape_name = nullptr);

/// A trajectory argument: a 2-D array of shape (rows, cols) or a sequence of `rows` 1-D arrays
/// of length `cols` (-1: any, but all rows of one length).
std::vector<Eigen::VectorXd> ToVectors(py::handle obj, const char* where, const char* name,
                                       Eigen::Index rows, Eigen::Index cols,
                                       const char* shape_name = nullptr);

/// A 4 x 4 homogeneous transform (last row 0 0 0 1, orthonormal rotation).
Eigen::Isometry3d ToIsometry(py::handle obj, const char* where, const char* name);

/// Copies into a new numpy array: 1-D for a vector, (size, n) for a list of vectors.
py::array_t<double> ToArray(const Eigen::VectorXd& x);
py::array_t<double> ToArray(const std::vector<Eigen::VectorXd>& x);
py::array_t<double> ToArray(const std::vector<double>& x);
py::array_t<double> ToArray(const Eigen::MatrixXd& x);

/// Throws IndexError unless 0 <= index < size.
void CheckIndex(const char* where, const char* name, long index, long size);

// ---- Errors raised by Python code inside a solve (callbacks, Ctrl-C). ----
/// Moves the current Python error (GIL held) into this thread's pending slot.
void StorePendingError();
bool HasPendingError();
/// Raises the pending error (as py::error_already_set), if any (GIL held).
void RaisePendingError();
/// Drops a pending error (GIL held).
void ClearPendingError();
/// True on the interpreter's main thread (the only one that handles signals); no GIL needed.
bool OnMainThread();
void RecordMainThread();

// ---- Registration, one function per binding file. ----
void BindModel(py::module_& m);
void BindProblem(py::module_& m);
void BindSolver(py::module_& m);
void BindConfig(py::module_& m);
void BindMpc(py::module_& m);
void BindSim(py::module_& m);
void BindTesting(py::module_& m);

}  // namespace idto::python
