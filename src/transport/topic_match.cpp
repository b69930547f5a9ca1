#include <nclink/topic_filter.hpp>

namespace nclink {

bool topic_matches(std::string_view filter, std::string_view topic) noexcept {
    if (filter.empty() || topic.empty()) return false;
    // MQTT 4.7.2: wildcards at the start never match $-topics ($SYS/...).
    if (topic.front() == '$' && (filter.front() == '+' || filter.front() == '#')) return false;
    std::size_t f = 0, t = 0;
    for (;;) {
        const std::size_t f_end = filter.find('/', f);
        const std::string_view f_level = filter.substr(f, f_end == std::string_view::npos ? std::string_view::npos : f_end - f);
        if (f_level == "#") return f_end == std::string_view::npos;  // '#' must be last
        const bool topic_done = t > topic.size();
        if (topic_done) return false;
        const std::size_t t_end = topic.find('/', t);
        const std::string_view t_level = topic.substr(t, t_end == std::string_view::npos ? std::string_view::npos : t_end - t);
        if (f_level != "+" && f_level != t_level) return false;
        const bool filter_last = f_end == std::string_view::npos;
        const bool topic_last = t_end == std::string_view::npos;
        if (filter_last || topic_last) {
            if (filter_last && topic_last) return true;
            // "a/#" matches "a" too: the parent level is included.
            if (topic_last && !filter_last) return filter.substr(f_end + 1) == "#";
            return false;
        }
        f = f_end + 1;
        t = t_end + 1;
    }
}

}  // namespace nclink
