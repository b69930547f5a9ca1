// One Sample DTU (8.2.15/8.2.21) as Python sees it: the rows of a channel
// between two uploads, each with its time. The DTU gives the first row's
// time (beginTime) and one column of values per point; row r was read at
// beginTime + r * sampleInterval, the interval coming from the model's
// SAMPLE_CHANNEL (or the dynamic channel's registration). The Python
// objects are built only when asked for (rows, columns, ...), so a callback
// that counts or forwards batches pays for no conversion.
#pragma once

#include <nclink/dtu.hpp>

#include <pybind11/pybind11.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace nclink::python {

namespace py = pybind11;

/// What a channel's rows mean: the point ids (columns) and the sample interval.
struct ChannelLayout {
    std::vector<std::string> ids;
    double interval_ms = 0;  ///< 0 = unknown: every row gets beginTime
};
using ChannelLayouts = std::map<std::string, ChannelLayout>;

class SampleBatch {
public:
    SampleBatch(std::string dev, SampleDtu dtu, const ChannelLayout* layout);

    const std::string& dev() const noexcept { return dev_; }
    const std::string& channel() const noexcept { return dtu_.id; }
    std::int64_t begin_time_ms() const noexcept { return dtu_.begin_time; }
    double interval_ms() const noexcept { return interval_ms_; }
    bool replayed() const noexcept { return replayed_; }
    std::size_t size() const noexcept { return rows_; }
    /// Column names: the layout's ids, or p1, p2, ... when the DTU has more points.
    py::list ids() const;
    /// Row times, ms since the epoch (float: intervals may be fractional).
    py::list times_ms() const;
    /// [(time_s, v1, v2, ...), ...]: time in seconds since the epoch like time.time().
    py::list rows() const;
    /// {id: [values...]} in row order.
    py::dict columns() const;
    /// The DTU as received (a dict).
    py::object raw() const;

private:
    double row_time_ms(std::size_t row) const noexcept;
    const Json* cell(std::size_t column, std::size_t row) const noexcept;

    std::string dev_;
    SampleDtu dtu_;
    std::vector<std::string> ids_;
    double interval_ms_ = 0;
    bool replayed_ = false;
    std::size_t rows_ = 0;
};

/// Fast scalar conversion for the hot path (falls back to to_python).
py::object cell_to_python(const Json& value);

void bind_sample_batch(py::module_& module);

}  // namespace nclink::python
