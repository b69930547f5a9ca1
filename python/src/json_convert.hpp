// JSON values between nclink (nlohmann::json) and Python objects: objects as
// dicts, arrays as lists, numbers as int/float, null as None. Needs the GIL.
#pragma once

#include <nclink/json.hpp>

#include <pybind11/pybind11.h>

namespace nclink::python {

namespace py = pybind11;

/// A JSON value as a Python object (dict, list, str, int, float, bool, None).
py::object to_python(const Json& value);
/// A Python value as JSON: dict (str keys), list/tuple, str, int, float, bool,
/// None. Anything else raises TypeError naming the type and where it is.
Json from_python(const py::handle& value);

}  // namespace nclink::python
