#include "core/prometheus_text.hpp"

#include <fmt/format.h>

#include <cmath>

namespace nclink::core_detail {
namespace {

// Length of the valid UTF-8 sequence at s[i], 0 when it is none.
std::size_t utf8_length(std::string_view s, std::size_t i) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t n = 0;
    unsigned min = 0;
    if (c < 0x80) return 1;
    if ((c & 0xE0) == 0xC0) n = 2, min = 0x80;
    else if ((c & 0xF0) == 0xE0) n = 3, min = 0x800;
    else if ((c & 0xF8) == 0xF0) n = 4, min = 0x10000;
    else return 0;
    if (i + n > s.size()) return 0;
    unsigned code = c & (0x7F >> n);
    for (std::size_t k = 1; k < n; ++k) {
        const auto d = static_cast<unsigned char>(s[i + k]);
        if ((d & 0xC0) != 0x80) return 0;
        code = (code << 6) | (d & 0x3F);
    }
    if (code < min || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
    return n;
}

std::string escape_help(std::string_view help) {
    std::string out;
    out.reserve(help.size());
    for (char c : help) {
        if (c == '\\') out += "\\\\";
        else if (c == '\n') out += "\\n";
        else out += c;
    }
    return out;
}

std::string label_text(const MetricLabels& labels, std::string_view extra_name = {}, std::string_view extra_value = {}) {
    if (labels.empty() && extra_name.empty()) return {};
    std::string out = "{";
    bool first = true;
    auto add = [&](std::string_view name, std::string_view value) {
        if (!first) out += ',';
        first = false;
        out.append(name);
        out += "=\"";
        out += escape_label_value(value);
        out += '"';
    };
    for (const auto& [name, value] : labels) add(name, value);
    if (!extra_name.empty()) add(extra_name, extra_value);
    out += '}';
    return out;
}

}  // namespace

std::string escape_label_value(std::string_view value) {
    std::string out;
    out.reserve(value.size());
    for (std::size_t i = 0; i < value.size();) {
        const char c = value[i];
        const std::size_t n = utf8_length(value, i);
        if (n == 0) {
            out += '?';
            ++i;
            continue;
        }
        if (c == '\\') out += "\\\\";
        else if (c == '"') out += "\\\"";
        else if (c == '\n') out += "\\n";
        else out.append(value.substr(i, n));
        i += n;
    }
    return out;
}

std::string format_metric_value(double value) {
    if (std::isnan(value)) return "NaN";
    if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
    if (value == std::floor(value) && std::fabs(value) < 1e15) return fmt::format("{}", static_cast<long long>(value));
    return fmt::format("{}", value);
}

PrometheusText::Family& PrometheusText::family(std::string_view name, std::string_view type, std::string_view help) {
    auto it = families_.find(name);
    if (it == families_.end()) {
        order_.emplace_back(name);
        it = families_.emplace(std::string(name), Family{std::string(type), std::string(help), {}}).first;
    }
    return it->second;
}

void PrometheusText::declare(std::string_view name, std::string_view type, std::string_view help) { family(name, type, help); }

void PrometheusText::counter(std::string_view name, std::string_view help, const MetricLabels& labels, std::uint64_t value) {
    auto& f = family(name, "counter", help);
    f.samples += fmt::format("{}{} {}\n", name, label_text(labels), value);
}

void PrometheusText::counter(std::string_view name, std::string_view help, const MetricLabels& labels, double value) {
    auto& f = family(name, "counter", help);
    f.samples += fmt::format("{}{} {}\n", name, label_text(labels), format_metric_value(value));
}

void PrometheusText::gauge(std::string_view name, std::string_view help, const MetricLabels& labels, double value) {
    auto& f = family(name, "gauge", help);
    f.samples += fmt::format("{}{} {}\n", name, label_text(labels), format_metric_value(value));
}

void PrometheusText::histogram(std::string_view name, std::string_view help, const MetricLabels& labels,
                               const HistogramSnapshot& h) {
    auto& f = family(name, "histogram", help);
    std::uint64_t cumulative = 0;
    for (std::size_t i = 0; i < h.upper_bounds.size(); ++i) {
        cumulative += i < h.counts.size() ? h.counts[i] : 0;
        f.samples +=
            fmt::format("{}_bucket{} {}\n", name, label_text(labels, "le", format_metric_value(h.upper_bounds[i])), cumulative);
    }
    // +Inf holds every observation; taken from the buckets so it can never
    // be below the last finite bucket.
    for (std::size_t i = h.upper_bounds.size(); i < h.counts.size(); ++i) cumulative += h.counts[i];
    f.samples += fmt::format("{}_bucket{} {}\n", name, label_text(labels, "le", "+Inf"), cumulative);
    f.samples += fmt::format("{}_sum{} {}\n", name, label_text(labels), format_metric_value(h.sum));
    f.samples += fmt::format("{}_count{} {}\n", name, label_text(labels), cumulative);
}

std::string PrometheusText::str() const {
    std::string out;
    for (const auto& name : order_) {
        const Family& f = families_.find(name)->second;
        out += fmt::format("# HELP {} {}\n# TYPE {} {}\n", name, escape_help(f.help), name, f.type);
        out += f.samples;
    }
    return out;
}

}  // namespace nclink::core_detail
