#include "http/router.hpp"

#include <algorithm>
#include <set>

namespace nclink::http {

std::vector<std::string_view> split_path(std::string_view path) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < path.size()) {
        if (path[i] == '/') {
            ++i;
            continue;
        }
        const std::size_t end = std::min(path.find('/', i), path.size());
        out.push_back(path.substr(i, end - i));
        i = end;
    }
    return out;
}

namespace {
bool is_param(std::string_view segment) { return segment.size() > 2 && segment.front() == '{' && segment.back() == '}'; }
}  // namespace

std::size_t Router::add(std::string method, std::string_view pattern) {
    Route route;
    route.method = std::move(method);
    route.pattern = std::string(pattern);
    for (auto segment : split_path(pattern)) {
        if (!is_param(segment)) ++route.literals;
        route.segments.emplace_back(segment);
    }
    routes_.push_back(std::move(route));
    return routes_.size() - 1;
}

Router::Match Router::match(std::string_view method, std::string_view path) const {
    const auto parts = split_path(path);
    const std::string_view wanted = method == "HEAD" ? std::string_view("GET") : method;
    Match best;
    std::set<std::string> allowed;
    bool found = false;
    std::size_t best_literals = 0;
    for (std::size_t r = 0; r < routes_.size(); ++r) {
        const Route& route = routes_[r];
        if (route.segments.size() != parts.size()) continue;
        bool ok = true;
        for (std::size_t i = 0; i < parts.size() && ok; ++i)
            if (!is_param(route.segments[i]) && route.segments[i] != parts[i]) ok = false;
        if (!ok) continue;
        allowed.insert(route.method);
        if (route.method == "GET") allowed.insert("HEAD");
        if (route.method != wanted) continue;
        if (found && route.literals <= best_literals) continue;
        found = true;
        best_literals = route.literals;
        best.route = r;
        best.params.clear();
        for (std::size_t i = 0; i < parts.size(); ++i)
            if (is_param(route.segments[i]))
                best.params[route.segments[i].substr(1, route.segments[i].size() - 2)] = std::string(parts[i]);
    }
    if (found) {
        best.kind = Match::Kind::found;
        return best;
    }
    best.kind = allowed.empty() ? Match::Kind::no_path : Match::Kind::no_method;
    best.allowed.assign(allowed.begin(), allowed.end());
    return best;
}

}  // namespace nclink::http
