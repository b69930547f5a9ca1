#include "mtconnect/shdr_line.hpp"

#include <cctype>
#include <cstdlib>

namespace nclink::mtconnect {

namespace {

std::string trim(std::string text) {
    std::size_t b = 0, e = text.size();
    while (b < e && std::isspace(static_cast<unsigned char>(text[b]))) ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(text[e - 1]))) --e;
    return text.substr(b, e - b);
}

}  // namespace

std::vector<std::string> shdr_fields(std::string_view line) {
    while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.remove_suffix(1);
    std::vector<std::string> out;
    std::size_t i = 0;
    for (;;) {
        // Leading spaces before a quote do not make the field unquoted.
        std::size_t j = i;
        while (j < line.size() && line[j] == ' ') ++j;
        if (j < line.size() && line[j] == '"') {
            // A quoted field: up to a '"' followed by '|' or the end.
            std::string field;
            std::size_t k = j + 1;
            bool closed = false;
            while (k < line.size()) {
                const char c = line[k];
                if (c == '\\' && k + 1 < line.size()) {
                    field += line[k + 1];
                    k += 2;
                    continue;
                }
                if (c == '"' && (k + 1 == line.size() || line[k + 1] == '|')) {
                    closed = true;
                    ++k;
                    break;
                }
                field += c;
                ++k;
            }
            if (!closed) {
                // No closing quote: the field is the raw text to the next '|'.
                const std::size_t bar = line.find('|', i);
                out.push_back(trim(std::string(line.substr(i, bar == std::string_view::npos ? std::string_view::npos : bar - i))));
                if (bar == std::string_view::npos) return out;
                i = bar + 1;
                continue;
            }
            out.push_back(field);
            if (k >= line.size()) return out;
            i = k + 1;  // past the '|'
            if (i == line.size()) {
                out.emplace_back();
                return out;
            }
            continue;
        }
        const std::size_t bar = line.find('|', i);
        if (bar == std::string_view::npos) {
            out.push_back(trim(std::string(line.substr(i))));
            return out;
        }
        out.push_back(trim(std::string(line.substr(i, bar - i))));
        i = bar + 1;
    }
}

long long shdr_pong_ms(std::string_view line) {
    const std::string_view head = "* PONG";
    if (line.substr(0, head.size()) != head) return -1;
    std::string rest(line.substr(head.size()));
    while (!rest.empty() && (rest.back() == '\r' || rest.back() == '\n' || rest.back() == ' ')) rest.pop_back();
    std::size_t b = rest.find_first_not_of(' ');
    if (b == std::string::npos) return -1;
    rest = rest.substr(b);
    if (rest.empty() || rest.size() > 9 || rest.find_first_not_of("0123456789") != std::string::npos) return -1;
    return std::atoll(rest.c_str());
}

std::pair<std::string, std::string> shdr_split_key(const std::string& key) {
    const std::size_t colon = key.find(':');
    if (colon == std::string::npos) return {{}, key};
    return {key.substr(0, colon), key.substr(colon + 1)};
}

}  // namespace nclink::mtconnect
