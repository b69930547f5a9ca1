// nclink errors as Python exceptions: one class per table-19 code under
// nclink.Error (python/nclink/_errors.py), each carrying code, reason and
// message. Needs the GIL.
#pragma once

#include <nclink/error.hpp>

#include <pybind11/pybind11.h>

#include <optional>
#include <string>

namespace nclink::python {

namespace py = pybind11;

/// The exception instance for a code (table 19, or a vendor's < 0), the
/// reason the peer sent (empty: table 19's) and a message for people.
py::object make_exception(int code, const std::string& reason, const std::string& message);
py::object make_exception(const Error& error);
/// Raises it (throws py::error_already_set with the Python error set).
[[noreturn]] void raise_error(const Error& error);
[[noreturn]] void raise_exception(const py::object& exception);

}  // namespace nclink::python
