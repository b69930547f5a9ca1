// Collects validator findings; JSON-pointer helpers (RFC 6901).
#pragma once

#include <nclink/model.hpp>

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nclink::model_detail {

/// "/a" + "b~c/d" -> "/a/b~0c~1d": a token is escaped so member names holding
/// '/' or '~' still give a pointer that resolves to them.
std::string pointer_append(std::string_view base, std::string_view token);
std::string pointer_append(std::string_view base, std::size_t index);

/// Problems in the order they were found (document order, then cross checks).
class Problems {
public:
    void add(Severity severity, std::string pointer, std::string message) {
        list_.push_back(Problem{severity, std::move(pointer), std::move(message)});
    }
    void fatal(std::string pointer, std::string message) { add(Severity::fatal, std::move(pointer), std::move(message)); }
    void conformance(std::string pointer, std::string message) {
        add(Severity::conformance, std::move(pointer), std::move(message));
    }
    void warning(std::string pointer, std::string message) { add(Severity::warning, std::move(pointer), std::move(message)); }
    bool has_fatal() const noexcept {
        for (const auto& p : list_)
            if (p.severity == Severity::fatal) return true;
        return false;
    }
    std::vector<Problem> take() { return std::move(list_); }

private:
    std::vector<Problem> list_;
};

}  // namespace nclink::model_detail
