// Entry points: bytes -> (problems, model). Decoding, JSON parsing and the
// tree walk are each in their own file; this one sequences them and makes
// sure nothing escapes as an exception.
#include "model/cross_check.hpp"
#include "model/encoding.hpp"
#include "model/model_builder.hpp"
#include "model/read_tree.hpp"

#include <nclink/model.hpp>

#include <fmt/format.h>

#include <fstream>
#include <iterator>
#include <new>
#include <sstream>

namespace nclink {
namespace {

// nlohmann parses iteratively but copies, compares and dumps recursively;
// bounding the nesting keeps hostile input from exhausting the stack.
constexpr std::size_t kMaxDepth = 256;

std::size_t nesting_depth(std::string_view text) {
    std::size_t depth = 0;
    std::size_t max_depth = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\') ++i;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            max_depth = std::max(max_depth, ++depth);
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return max_depth;
}

std::string parse_error_message(const std::string& what) {
    // "[json.exception.parse_error.101] parse error at line 1, column 2: ..." -> from "parse error"
    const auto pos = what.find("] ");
    return pos == std::string::npos ? what : what.substr(pos + 2);
}

LoadResult parse_utf8(std::string_view text, model_detail::Problems& problems) {
    LoadResult result;
    if (nesting_depth(text) > kMaxDepth) {
        problems.fatal("", fmt::format("not a usable model: JSON nested deeper than {} levels", kMaxDepth));
        result.problems = problems.take();
        return result;
    }
    Json document;
    try {
        document = Json::parse(text.begin(), text.end());
    } catch (const Json::exception& e) {
        problems.fatal("", "not JSON: " + parse_error_message(e.what()));
        result.problems = problems.take();
        return result;
    }
    ModelBuilder builder(problems);
    const auto outcome = model_detail::read_document(document, problems, builder);
    model_detail::check_channel_references(builder.model(), outcome.channel_references, problems);
    model_detail::check_fixed_values(builder.model(), problems);
    if (!problems.has_fatal()) {
        result.model = builder.finish();
        // As provided, for Probe/Query (8.2.8); a byte order mark is not JSON text.
        constexpr std::string_view bom = "\xEF\xBB\xBF";
        if (text.substr(0, bom.size()) == bom) text.remove_prefix(bom.size());
        result.document = std::make_shared<const std::string>(text);
    }
    result.problems = problems.take();
    return result;
}

}  // namespace

LoadResult parse_model(std::string_view text) {
    model_detail::Problems problems;
    try {
        if (model_detail::is_valid_utf8(text)) return parse_utf8(text, problems);
        auto converted = model_detail::gbk_to_utf8(text);
        if (!converted) {
            problems.fatal("", "not a usable model: the file is neither UTF-8 nor GBK");
            return LoadResult{problems.take(), nullptr, nullptr};
        }
        problems.conformance("",
                             "file is GBK-encoded, converted to UTF-8 (the standard "
                             "requires UTF-8)");
        return parse_utf8(*converted, problems);
    } catch (const std::bad_alloc&) {
        model_detail::Problems oom;
        oom.fatal("", "out of memory while loading the model");
        return LoadResult{oom.take(), nullptr, nullptr};
    } catch (const std::exception& e) {
        // Defensive: the reader only uses non-throwing accessors, but a model
        // loader must never take the firmware down.
        model_detail::Problems internal;
        internal.fatal("", std::string("internal error while loading the model: ") + e.what());
        return LoadResult{internal.take(), nullptr, nullptr};
    }
}

LoadResult load_model_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        model_detail::Problems problems;
        problems.fatal("", fmt::format("cannot open \"{}\"", path));
        return LoadResult{problems.take(), nullptr, nullptr};
    }
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) {
        model_detail::Problems problems;
        problems.fatal("", fmt::format("cannot read \"{}\"", path));
        return LoadResult{problems.take(), nullptr, nullptr};
    }
    return parse_model(buffer.str());
}

}  // namespace nclink
