// Recursive conversion both ways. Python ints outside the 64-bit range and
// other types raise TypeError/OverflowError instead of being truncated: a
// value the application meant is never sent changed.
#include "json_convert.hpp"

#include <cmath>
#include <string>

namespace nclink::python {

py::object to_python(const Json& value) {
    switch (value.type()) {
        case Json::value_t::null: return py::none();
        case Json::value_t::boolean: return py::bool_(value.get<bool>());
        case Json::value_t::number_integer: return py::int_(value.get<std::int64_t>());
        case Json::value_t::number_unsigned: return py::int_(value.get<std::uint64_t>());
        case Json::value_t::number_float: return py::float_(value.get<double>());
        case Json::value_t::string: return py::str(value.get_ref<const std::string&>());
        case Json::value_t::array: {
            py::list out(value.size());
            std::size_t i = 0;
            for (const auto& element : value) out[i++] = to_python(element);
            return std::move(out);
        }
        case Json::value_t::object: {
            py::dict out;
            for (auto it = value.begin(); it != value.end(); ++it) out[py::str(it.key())] = to_python(it.value());
            return std::move(out);
        }
        case Json::value_t::binary:
        case Json::value_t::discarded: break;
    }
    return py::none();
}

namespace {

Json convert(const py::handle& value, const std::string& where) {
    if (value.is_none()) return Json(nullptr);
    if (py::isinstance<py::bool_>(value)) return Json(value.cast<bool>());
    if (py::isinstance<py::int_>(value)) {
        int overflow = 0;
        const long long n = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
        if (overflow == 0) return Json(static_cast<std::int64_t>(n));
        if (overflow > 0) {
            const unsigned long long u = PyLong_AsUnsignedLongLong(value.ptr());
            if (!PyErr_Occurred()) return Json(static_cast<std::uint64_t>(u));
            PyErr_Clear();
        }
        throw py::value_error("integer out of the 64-bit range at " + (where.empty() ? std::string("/") : where));
    }
    if (py::isinstance<py::float_>(value)) return Json(value.cast<double>());
    if (py::isinstance<py::str>(value)) return Json(value.cast<std::string>());
    if (py::isinstance<py::dict>(value)) {
        Json out = Json::object();
        for (auto item : py::reinterpret_borrow<py::dict>(value)) {
            if (!py::isinstance<py::str>(item.first))
                throw py::type_error("JSON object keys must be str (at " + (where.empty() ? std::string("/") : where) + ")");
            auto key = item.first.cast<std::string>();
            out[key] = convert(item.second, where + "/" + key);
        }
        return out;
    }
    if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
        Json out = Json::array();
        std::size_t i = 0;
        for (auto element : value) out.push_back(convert(element, where + "/" + std::to_string(i++)));
        return out;
    }
    // numpy scalars and other numbers: anything with __float__/__index__.
    if (PyIndex_Check(value.ptr())) {
        PyObject* index = PyNumber_Index(value.ptr());
        if (!index) throw py::error_already_set();
        return convert(py::reinterpret_steal<py::object>(index), where);
    }
    if (PyFloat_Check(value.ptr()) || py::hasattr(value, "__float__")) {
        const double d = PyFloat_AsDouble(value.ptr());
        if (d == -1.0 && PyErr_Occurred()) throw py::error_already_set();
        return Json(d);
    }
    throw py::type_error("cannot send a " + std::string(py::str(value.get_type().attr("__name__"))) + " as JSON (at " +
                         (where.empty() ? std::string("/") : where) + ")");
}

}  // namespace

Json from_python(const py::handle& value) { return convert(value, ""); }

}  // namespace nclink::python
