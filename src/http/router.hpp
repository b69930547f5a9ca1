// Route table of the HTTP server: patterns with "{name}" segments, matched
// per method; tells a 404 (no pattern matches the path) from a 405 (patterns
// match, but none for this method) and which methods the path allows.
// Not synchronized: filled before serving, then only read.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::http {

class Router {
public:
    /// Adds a route; returns its index (handlers are kept by the caller).
    std::size_t add(std::string method, std::string_view pattern);

    struct Match {
        enum class Kind { found, no_path, no_method } kind = Kind::no_path;
        std::size_t route = 0;                      ///< found: the route index
        std::map<std::string, std::string> params;  ///< found: path parameters
        std::vector<std::string> allowed;           ///< no_method: methods the path has (sorted, HEAD with GET)
    };
    /// The route for `method` and `path` (HEAD uses the GET routes). Among
    /// several matching patterns the one with the most literal segments wins,
    /// then the earliest added.
    Match match(std::string_view method, std::string_view path) const;
    /// The pattern a route was added with.
    const std::string& pattern(std::size_t route) const { return routes_.at(route).pattern; }

private:
    struct Route {
        std::string method;
        std::string pattern;
        std::vector<std::string> segments;  ///< "{x}" = parameter x
        std::size_t literals = 0;
    };
    std::vector<Route> routes_;
};

/// "/a/b/" -> {"a", "b"}; empty segments dropped except that "/" is no segments.
std::vector<std::string_view> split_path(std::string_view path);

}  // namespace nclink::http
