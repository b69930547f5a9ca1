// Checks a Prometheus text exposition (format 0.0.4) in tests, two ways:
//  - exposition_problems(): an independent reader of the format's rules
//    (metric and label name syntax, quoting and escapes, HELP/TYPE once per
//    family and before its samples, a family's samples together, counters
//    ending in _total, histogram buckets ascending in le and cumulative, a
//    +Inf bucket equal to _count); returns every problem found;
//  - promtool_problems(): `promtool check metrics` from Debian's prometheus
//    package when it is installed (nullopt when not: the test says so).
// No Catch assertion in here.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace nclink::test {

struct PromSample {
    std::string name;
    std::map<std::string, std::string> labels;
    double value = 0;
};

// Parses `{a="x",b="y"}` at text[i]; false on a syntax error.
inline bool parse_prom_labels(const std::string& text, std::size_t& i, std::map<std::string, std::string>& out,
                              std::string& problem) {
    static const std::regex label_name("[a-zA-Z_][a-zA-Z0-9_]*");
    ++i;  // '{'
    while (i < text.size() && text[i] != '}') {
        const auto eq = text.find('=', i);
        if (eq == std::string::npos) return problem = "label without '='", false;
        const std::string name = text.substr(i, eq - i);
        if (!std::regex_match(name, label_name)) return problem = "bad label name '" + name + "'", false;
        i = eq + 1;
        if (i >= text.size() || text[i] != '"') return problem = "label value not quoted", false;
        ++i;
        std::string value;
        while (i < text.size() && text[i] != '"') {
            if (text[i] == '\\') {
                if (i + 1 >= text.size()) return problem = "dangling escape", false;
                const char e = text[i + 1];
                if (e == 'n') value += '\n';
                else if (e == '\\' || e == '"') value += e;
                else return problem = std::string("bad escape \\") + e, false;
                i += 2;
            } else if (text[i] == '\n') {
                return problem = "line feed in a label value", false;
            } else {
                value += text[i++];
            }
        }
        if (i >= text.size()) return problem = "unterminated label value", false;
        ++i;  // closing quote
        if (out.count(name)) return problem = "label " + name + " twice", false;
        out[name] = value;
        if (i < text.size() && text[i] == ',') ++i;
    }
    if (i >= text.size()) return problem = "unterminated label set", false;
    ++i;  // '}'
    return true;
}

inline std::optional<double> parse_prom_value(const std::string& text) {
    if (text == "+Inf") return HUGE_VAL;
    if (text == "-Inf") return -HUGE_VAL;
    if (text == "NaN") return std::nan("");
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0') return std::nullopt;
    return v;
}

inline std::vector<std::string> exposition_problems(const std::string& text, std::vector<PromSample>* samples_out = nullptr) {
    static const std::regex metric_name("[a-zA-Z_:][a-zA-Z0-9_:]*");
    std::vector<std::string> problems;
    std::map<std::string, std::string> types;  // family -> type
    std::set<std::string> helped, closed;      // families with HELP; families whose samples ended
    std::string current;                       // the family of the last line
    std::vector<PromSample> samples;
    std::istringstream in(text);
    std::string line;
    int number = 0;
    if (!text.empty() && text.back() != '\n') problems.push_back("the text does not end with a line feed");
    auto family_of = [&](const std::string& name) {
        for (const char* suffix : {"_bucket", "_sum", "_count"}) {
            const std::string s = suffix;
            if (name.size() > s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0) {
                const std::string base = name.substr(0, name.size() - s.size());
                if (types.count(base) && types[base] == "histogram") return base;
            }
        }
        return name;
    };
    auto enter = [&](const std::string& family, int at) {
        if (family == current) return;
        if (!current.empty()) closed.insert(current);
        if (closed.count(family))
            problems.push_back("line " + std::to_string(at) + ": samples of " + family + " are not together");
        current = family;
    };
    while (std::getline(in, line)) {
        ++number;
        const std::string at = "line " + std::to_string(number) + ": ";
        if (line.empty()) continue;
        if (line[0] == '#') {
            std::istringstream words(line);
            std::string hash, keyword, name;
            words >> hash >> keyword >> name;
            if (keyword != "HELP" && keyword != "TYPE") continue;  // a comment
            if (!std::regex_match(name, metric_name)) problems.push_back(at + "bad metric name '" + name + "'");
            enter(name, number);
            if (keyword == "HELP") {
                if (!helped.insert(name).second) problems.push_back(at + "second HELP of " + name);
            } else {
                std::string type;
                words >> type;
                if (types.count(name)) problems.push_back(at + "second TYPE of " + name);
                if (type != "counter" && type != "gauge" && type != "histogram" && type != "summary" && type != "untyped")
                    problems.push_back(at + "unknown type '" + type + "'");
                for (const auto& s : samples)
                    if (family_of(s.name) == name) problems.push_back(at + "TYPE of " + name + " after its samples");
                types[name] = type;
                if (type == "counter" && (name.size() < 6 || name.compare(name.size() - 6, 6, "_total") != 0))
                    problems.push_back(at + "counter " + name + " does not end in _total");
            }
            continue;
        }
        PromSample s;
        std::size_t i = 0;
        while (i < line.size() && line[i] != '{' && line[i] != ' ') ++i;
        s.name = line.substr(0, i);
        if (!std::regex_match(s.name, metric_name)) problems.push_back(at + "bad metric name '" + s.name + "'");
        std::string problem;
        if (i < line.size() && line[i] == '{' && !parse_prom_labels(line, i, s.labels, problem)) problems.push_back(at + problem);
        if (i >= line.size() || line[i] != ' ') {
            problems.push_back(at + "no value");
            continue;
        }
        std::istringstream rest(line.substr(i + 1));
        std::string value_text, timestamp;
        rest >> value_text >> timestamp;
        const auto value = parse_prom_value(value_text);
        if (!value) problems.push_back(at + "bad value '" + value_text + "'");
        s.value = value.value_or(0);
        const std::string family = family_of(s.name);
        if (!types.count(family)) problems.push_back(at + s.name + " has no TYPE");
        enter(family, number);
        samples.push_back(std::move(s));
    }
    // Histograms: buckets ascending and cumulative, +Inf == _count.
    std::map<std::string, std::vector<std::pair<double, double>>> buckets;  // family+labels -> (le, n)
    std::map<std::string, double> counts;
    for (const auto& s : samples) {
        const std::string family = family_of(s.name);
        if (types[family] != "histogram") continue;
        auto labels = s.labels;
        const auto le = labels.find("le");
        std::optional<double> bound;
        if (le != labels.end()) {
            bound = parse_prom_value(le->second);
            labels.erase(le);
        }
        std::string key = family;
        for (const auto& [k, v] : labels) key += "," + k + "=" + v;
        if (s.name == family + "_bucket") {
            if (!bound) problems.push_back(s.name + ": a bucket without le");
            else buckets[key].emplace_back(*bound, s.value);
        } else if (s.name == family + "_count") {
            counts[key] = s.value;
        }
    }
    for (const auto& [key, list] : buckets) {
        for (std::size_t k = 1; k < list.size(); ++k) {
            if (!(list[k].first > list[k - 1].first)) problems.push_back(key + ": le not ascending");
            if (list[k].second < list[k - 1].second) problems.push_back(key + ": buckets not cumulative");
        }
        if (list.empty() || !std::isinf(list.back().first)) problems.push_back(key + ": no +Inf bucket");
        else if (!counts.count(key) || counts[key] != list.back().second)
            problems.push_back(key + ": _count is not the +Inf bucket");
    }
    if (samples_out) *samples_out = std::move(samples);
    return problems;
}

/// promtool's complaints about `text` (empty: none); nullopt when promtool
/// is not installed.
inline std::optional<std::string> promtool_problems(const std::string& text) {
    if (std::system("command -v promtool >/dev/null 2>&1") != 0) return std::nullopt;
    const std::string base = "/tmp/nclink-promtool-" + std::to_string(std::random_device{}());
    std::ofstream(base + ".txt", std::ios::binary) << text;
    const int status = std::system(("promtool check metrics < " + base + ".txt > " + base + ".out 2>&1").c_str());
    std::ifstream in(base + ".out");
    std::stringstream out;
    out << in.rdbuf();
    std::remove((base + ".txt").c_str());
    std::remove((base + ".out").c_str());
    std::string said = out.str();
    if (status != 0 && said.empty()) said = "promtool failed";
    return status == 0 ? std::string() : said;
}

/// The value of the sample `name` with exactly these labels, if present.
inline std::optional<double> prom_value(const std::vector<PromSample>& samples, const std::string& name,
                                        const std::map<std::string, std::string>& labels = {}) {
    for (const auto& s : samples)
        if (s.name == name && s.labels == labels) return s.value;
    return std::nullopt;
}

}  // namespace nclink::test
