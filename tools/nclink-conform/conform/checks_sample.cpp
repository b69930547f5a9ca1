// The sample checks of the conformance run (8.2.18, tables 58-59): one
// Sample DTU's shape against its channel, and a run of them against the
// channel's intervals.
#include "conform/checks.hpp"
#include "conform/check_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace nclink::conform {

using namespace check_text;

double ChannelSpec::expected_rows() const {
    if (!(sample_ms > 0) || !(upload_ms > 0)) return 1;
    return std::max(1.0, upload_ms / sample_ms);
}

bool plausible_epoch_ms(std::int64_t ms) { return ms >= 946'684'800'000LL && ms < 4'102'444'800'000LL; }

SampleCheck check_sample_dtu(const Json& dtu, std::string_view dev, const ChannelSpec& spec) {
    SampleCheck out;
    Problems& p = out.problems;
    add_all(p, check_envelope(dtu, Json(), dev, true));
    expect_string(p, dtu, "id", spec.id, "table 36/42");
    if (spec.id.size() > 16) p.push_back(fmt::format("channel id \"{}\" is longer than 16 bytes (table 36)", spec.id));

    std::optional<std::int64_t> begin;
    auto bt = dtu.find("beginTime");
    if (bt == dtu.end()) {
        p.push_back("\"beginTime\" is missing (table 36)");
    } else if (bt->is_string()) {
        const std::string& text = bt->get_ref<const std::string&>();
        if (!text.empty() && text.size() < 19 && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
            begin = std::stoll(text);
        else p.push_back(fmt::format("\"beginTime\" is \"{}\", not milliseconds since the epoch", text));
    } else if (bt->is_number_integer()) {
        begin = bt->get<std::int64_t>();
        p.push_back("\"beginTime\" is a number; table 36 and docs/wire.md want a string");
    } else {
        p.push_back(fmt::format("\"beginTime\" is {}, not a string of milliseconds", show(*bt)));
    }
    if (begin && !plausible_epoch_ms(*begin))
        p.push_back(fmt::format("\"beginTime\" {} is not a time in milliseconds since the epoch (seconds? relative?)", *begin));

    auto data = dtu.find("data");
    if (data == dtu.end() || !data->is_array()) {
        p.push_back(data == dtu.end() ? "\"data\" is missing (table 36)" : "\"data\" is not an array");
        return out;
    }
    if (data->size() != spec.columns)
        p.push_back(
            fmt::format("\"data\" has {} entries; channel \"{}\" samples {} data items (table 36: order and number "
                        "shall match the model)",
                        data->size(), spec.id, spec.columns));
    std::optional<std::size_t> rows;
    bool ragged = false;
    for (std::size_t i = 0; i < data->size(); ++i) {
        const Json& col = (*data)[i];
        const Json* series = nullptr;
        if (col.is_object() && col.contains("data") && col["data"].is_array()) series = &col["data"];
        if (!series) {
            p.push_back(fmt::format("data[{}] is {}, expected {{\"data\": [...]}}", i, show(col, 80)));
            continue;
        }
        if (!rows) rows = series->size();
        else if (*rows != series->size()) ragged = true;
    }
    if (ragged) {
        std::string sizes;
        for (const auto& col : *data)
            sizes += (sizes.empty() ? "" : ",") + (col.is_object() && col.contains("data") && col["data"].is_array()
                                                       ? std::to_string(col["data"].size())
                                                       : std::string("?"));
        p.push_back(fmt::format("columns have different numbers of values ({}); each holds the same points in time", sizes));
    }
    if (rows && *rows == 0) p.push_back("a Sample DTU with no values");
    const double expected = spec.expected_rows();
    if (rows && *rows > 2 * std::ceil(expected) + 1)
        p.push_back(fmt::format("{} values per column; sampleInterval {} ms and uploadInterval {} ms give about {}", *rows,
                                spec.sample_ms, spec.upload_ms, expected));
    if (begin && rows) out.shape = SampleShape{*begin, *rows};
    return out;
}

namespace {
template <class T>
T median(std::vector<T> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}
}  // namespace

Problems check_sample_sequence(const std::vector<SampleArrival>& run, const ChannelSpec& spec) {
    Problems out;
    if (run.size() < 2) return out;
    const double tolerance = std::max({2 * spec.sample_ms, 0.1 * spec.upload_ms, 20.0});
    std::size_t reported = 0;
    for (std::size_t i = 0; i + 1 < run.size(); ++i) {
        const auto& a = run[i];
        const auto& b = run[i + 1];
        const double next = static_cast<double>(a.begin_time) + static_cast<double>(a.rows) * spec.sample_ms;
        const double gap = static_cast<double>(b.begin_time) - next;
        if (b.begin_time <= a.begin_time) {
            out.push_back(fmt::format("DTU {}: beginTime {} does not follow the previous {}", i + 1, b.begin_time, a.begin_time));
        } else if (std::abs(gap) > tolerance && reported < 3) {
            ++reported;
            out.push_back(
                fmt::format("DTU {}: beginTime {} but the previous DTU ({} values from {}, every {} ms) ends at {}: "
                            "{} {} ms (tolerance {} ms)",
                            i + 1, b.begin_time, a.rows, a.begin_time, spec.sample_ms, next,
                            gap > 0 ? "a gap of" : "an overlap of", std::abs(gap), tolerance));
        }
    }
    // Rows and pace: medians over the run without the first DTU (a channel may
    // start mid-period).
    if (run.size() >= 3) {
        const double expected = spec.expected_rows();
        std::vector<std::size_t> rows;
        std::vector<std::int64_t> gaps;
        for (std::size_t i = 1; i < run.size(); ++i) {
            rows.push_back(run[i].rows);
            gaps.push_back(run[i].arrived_ms - run[i - 1].arrived_ms);
        }
        const auto r = static_cast<double>(median(rows));
        if (r < 0.5 * expected || r > 1.5 * expected + 1)
            out.push_back(
                fmt::format("a DTU carries {} values per column (median); sampleInterval {} ms and uploadInterval {} ms "
                            "give {}",
                            r, spec.sample_ms, spec.upload_ms, expected));
        const double period = std::max(spec.upload_ms, spec.sample_ms);
        const auto g = static_cast<double>(median(gaps));
        if (g < 0.5 * period - 50 || g > 1.5 * period + 100)
            out.push_back(fmt::format("DTUs arrive every {} ms (median); uploadInterval is {} ms", g, spec.upload_ms));
    }
    return out;
}

}  // namespace nclink::conform
