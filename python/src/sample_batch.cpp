#include "sample_batch.hpp"

#include "json_convert.hpp"

#include <nclink/client.hpp>

#include <algorithm>
#include <cmath>

namespace nclink::python {

SampleBatch::SampleBatch(std::string dev, SampleDtu dtu, const ChannelLayout* layout)
    : dev_(std::move(dev)), dtu_(std::move(dtu)) {
    if (!dtu_.guid.empty()) dev_ = dtu_.guid;
    if (layout) {
        ids_ = layout->ids;
        interval_ms_ = layout->interval_ms;
    }
    // A point with a scalar instead of an array is one row (liberal).
    for (const auto& column : dtu_.data) rows_ = std::max(rows_, column.is_array() ? column.size() : std::size_t{1});
    for (std::size_t i = ids_.size(); i < dtu_.data.size(); ++i) ids_.push_back("p" + std::to_string(i + 1));
    replayed_ = Client::is_replayed(dtu_);
}

double SampleBatch::row_time_ms(std::size_t row) const noexcept {
    return static_cast<double>(dtu_.begin_time) + static_cast<double>(row) * interval_ms_;
}

const Json* SampleBatch::cell(std::size_t column, std::size_t row) const noexcept {
    const Json& values = dtu_.data[column];
    if (!values.is_array()) return row == 0 ? &values : nullptr;
    return row < values.size() ? &values[row] : nullptr;
}

py::object cell_to_python(const Json& value) {
    switch (value.type()) {
        case Json::value_t::number_float: return py::reinterpret_steal<py::object>(PyFloat_FromDouble(value.get<double>()));
        case Json::value_t::number_integer:
            return py::reinterpret_steal<py::object>(PyLong_FromLongLong(value.get<std::int64_t>()));
        case Json::value_t::null: return py::none();
        default: return to_python(value);
    }
}

py::list SampleBatch::ids() const {
    py::list out(dtu_.data.size());
    for (std::size_t i = 0; i < dtu_.data.size(); ++i) out[i] = py::str(ids_[i]);
    return out;
}

py::list SampleBatch::times_ms() const {
    py::list out(rows_);
    for (std::size_t r = 0; r < rows_; ++r) out[r] = py::float_(row_time_ms(r));
    return out;
}

py::list SampleBatch::rows() const {
    const std::size_t width = dtu_.data.size();
    PyObject* list = PyList_New(static_cast<Py_ssize_t>(rows_));
    if (!list) throw py::error_already_set();
    py::list out = py::reinterpret_steal<py::list>(list);
    for (std::size_t r = 0; r < rows_; ++r) {
        PyObject* row = PyTuple_New(static_cast<Py_ssize_t>(width + 1));
        if (!row) throw py::error_already_set();
        PyList_SET_ITEM(list, static_cast<Py_ssize_t>(r), row);  // the list owns it from here
        PyObject* time = PyFloat_FromDouble(row_time_ms(r) / 1000.0);
        if (!time) throw py::error_already_set();
        PyTuple_SET_ITEM(row, 0, time);
        for (std::size_t c = 0; c < width; ++c) {
            const Json* value = cell(c, r);
            py::object cell_object = value ? cell_to_python(*value) : py::none();
            PyTuple_SET_ITEM(row, static_cast<Py_ssize_t>(c + 1), cell_object.release().ptr());
        }
    }
    return out;
}

py::dict SampleBatch::columns() const {
    py::dict out;
    for (std::size_t c = 0; c < dtu_.data.size(); ++c) {
        py::list values(rows_);
        for (std::size_t r = 0; r < rows_; ++r) {
            const Json* value = cell(c, r);
            values[r] = value ? cell_to_python(*value) : py::none();
        }
        out[py::str(ids_[c])] = std::move(values);
    }
    return out;
}

py::object SampleBatch::raw() const { return to_python(to_json(dtu_)); }

void bind_sample_batch(py::module_& module) {
    py::class_<SampleBatch, std::shared_ptr<SampleBatch>>(module, "SampleBatch",
                                                          "The rows of one Sample DTU (8.2.15/8.2.21): one upload of a channel.")
        .def_property_readonly("dev", &SampleBatch::dev)
        .def_property_readonly("channel", &SampleBatch::channel)
        .def_property_readonly("begin_time_ms", &SampleBatch::begin_time_ms)
        .def_property_readonly("interval_ms", &SampleBatch::interval_ms)
        .def_property_readonly("replayed", &SampleBatch::replayed)
        .def_property_readonly("ids", &SampleBatch::ids)
        .def_property_readonly("times_ms", &SampleBatch::times_ms)
        .def_property_readonly("rows", &SampleBatch::rows)
        .def_property_readonly("columns", &SampleBatch::columns)
        .def("raw", &SampleBatch::raw)
        .def("__len__", &SampleBatch::size)
        .def("__repr__", [](const SampleBatch& b) {
            return "<SampleBatch " + b.dev() + "/" + b.channel() + " rows=" + std::to_string(b.size()) +
                   " begin_time_ms=" + std::to_string(b.begin_time_ms()) + ">";
        });
}

}  // namespace nclink::python
