// A program built against an installed nclink.
#include <nclink/error.hpp>
#include <nclink/result.hpp>
#include <nclink/version.hpp>

#include <cstdio>
#include <string>

int main() {
    nclink::Result<int> r = nclink::make_error(nclink::ErrorCode::node_not_exists, "no item 'X'");
    const std::string text = r.error().describe();
    std::printf("nclink %s: %s\n", nclink::library_version(), text.c_str());
    return r.ok() ? 1 : 0;
}
