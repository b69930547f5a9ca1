#include "errors.hpp"

namespace nclink::python {

py::object make_exception(int code, const std::string& reason, const std::string& message) {
    // Looked up at each error (errors are rare): the module is imported once
    // by `import nclink` and stays in sys.modules.
    auto from_code = py::module_::import("nclink._errors").attr("from_code");
    return from_code(code, reason, message);
}

py::object make_exception(const Error& error) {
    return make_exception(to_int(error.code), std::string(reason(error.code)), error.message);
}

void raise_exception(const py::object& exception) {
    PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(exception.ptr())), exception.ptr());
    throw py::error_already_set();
}

void raise_error(const Error& error) { raise_exception(make_exception(error)); }

}  // namespace nclink::python
