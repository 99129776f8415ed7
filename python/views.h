// NumPy arrays that view the library's own arrays instead of copying them, read-only.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hapticut::python {

/// A read-only NumPy array over `rows` rows of `columns` T's at `data` (`columns` 0: one T a row), with
/// `owner` as its base, kept alive while the array lives.
template <class T>
pybind11::array readOnlyView(const T* data, std::size_t rows, std::size_t columns, std::size_t rowBytes,
                             const pybind11::object& owner) {
    namespace py = pybind11;
    std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(rows)}, strides{static_cast<py::ssize_t>(rowBytes)};
    if (columns > 0) {
        shape.push_back(static_cast<py::ssize_t>(columns));
        strides.push_back(sizeof(T));
    }
    py::array view(py::dtype::of<T>(), shape, strides, data, owner);
    view.attr("setflags")(py::arg("write") = false);
    return view;
}

/// Each vertex's index in the file it came from: `previous` when the load renumbered the vertices
/// (mesh/vertex_order.h), otherwise 0, 1, ..., count - 1. A copy.
inline pybind11::array_t<std::uint32_t> fileVertices(const std::vector<std::uint32_t>& previous, std::size_t count) {
    pybind11::array_t<std::uint32_t> out(static_cast<pybind11::ssize_t>(count));
    std::uint32_t* to = out.mutable_data();
    for (std::size_t i = 0; i < count; ++i) to[i] = previous.empty() ? static_cast<std::uint32_t>(i) : previous[i];
    return out;
}

}  // namespace hapticut::python
