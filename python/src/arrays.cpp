// Array conversions: no copy for float64 C-contiguous input, one explicit copy otherwise,
// a ValueError naming the argument for a shape or dtype that cannot be meant.

#include <string>

#include "bindings.hpp"

namespace kincal::python {

namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// A numpy array of `value`, without a copy when it is one; a dtype kincal cannot read as
// real numbers is an error, not a conversion.
py::array as_array(const py::handle& value, const char* argument) {
  py::array a = py::array::ensure(value);
  if (!a) throw py::value_error(std::string(argument) + ": expected an array of numbers");
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::value_error(std::string(argument) + ": expected real numbers (float64), got dtype " +
                          std::string(py::str(a.dtype())));
  return a;
}

// float64 in C order: the same array, or one copy.
py::array_t<double, py::array::c_style> c_float64(const py::array& a) {
  return py::array_t<double, py::array::c_style>::ensure(a);
}

}  // namespace

py::array_t<double, py::array::c_style> as_rows(const py::handle& value, const char* argument,
                                                py::ssize_t cols) {
  py::array a = as_array(value, argument);
  const std::string expected = "(n, " + std::to_string(cols) + ")";
  if (a.ndim() == 1 && a.shape(0) == cols) a = py::array(a.attr("reshape")(1, cols));
  if (a.ndim() != 2 || a.shape(1) != cols) {
    std::string hint;
    if (a.ndim() == 2 && a.shape(0) == cols && a.shape(1) != cols)
      hint = " (transposed? one row per configuration)";
    throw py::value_error(std::string(argument) + ": expected shape " + expected + ", got " +
                          shape_text(a) + hint);
  }
  return c_float64(a);
}

py::array_t<double, py::array::c_style> as_vector(const py::handle& value, const char* argument,
                                                  py::ssize_t size) {
  py::array a = as_array(value, argument);
  if (a.ndim() != 1 || (size >= 0 && a.shape(0) != size))
    throw py::value_error(std::string(argument) + ": expected shape (" +
                          (size >= 0 ? std::to_string(size) : std::string("n")) + ",), got " +
                          shape_text(a));
  return c_float64(a);
}

py::array_t<double> to_numpy(const MatrixXd& m) {
  py::array_t<double> out({m.rows(), m.cols()});
  Eigen::Map<RowMatrixXd>(out.mutable_data(), m.rows(), m.cols()) = m;
  return out;
}

py::array_t<double> to_numpy(const VectorXd& v) {
  py::array_t<double> out(v.size());
  Eigen::Map<VectorXd>(out.mutable_data(), v.size()) = v;
  return out;
}

}  // namespace kincal::python
