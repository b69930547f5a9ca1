// Topic building, parsing and the mirror rule. One table of shapes drives
// both directions so builder and parser cannot drift apart.
#include <nclink/topics.hpp>

#include <array>

namespace nclink {
namespace {

/// What follows the literal prefix of a topic.
enum class Params {
    none,            // Register/Request
    one,             // {dev} (or cli / tid)
    ex_only,         // {ex} (Discovery)
    dev_opt_ex,      // {dev}[/{ex}]
    dev_channel,     // {dev}/{channel}
    dev_ex_channel,  // {dev}/{ex}/{channel}
};

struct Shape {
    TopicKind kind;
    std::array<std::string_view, 3> prefix;
    std::size_t prefix_size;
    Params params;
    std::string_view name;
};

// Longer prefixes first, so "Probe/Version/Response/x" is not read as
// Probe/Version with dev "Response".
constexpr std::array<Shape, 31> kShapes{{
    {TopicKind::probe_version_response, {"Probe", "Version", "Response"}, 3, Params::dev_opt_ex, "probe_version_response"},
    {TopicKind::probe_query_request, {"Probe", "Query", "Request"}, 3, Params::dev_opt_ex, "probe_query_request"},
    {TopicKind::probe_query_response, {"Probe", "Query", "Response"}, 3, Params::dev_opt_ex, "probe_query_response"},
    {TopicKind::probe_set_request, {"Probe", "Set", "Request"}, 3, Params::dev_opt_ex, "probe_set_request"},
    {TopicKind::probe_set_response, {"Probe", "Set", "Response"}, 3, Params::dev_opt_ex, "probe_set_response"},
    {TopicKind::sample_register_request, {"Register", "Sample", "Request"}, 3, Params::dev_opt_ex, "sample_register_request"},
    {TopicKind::sample_register_response, {"Register", "Sample", "Response"}, 3, Params::dev_opt_ex, "sample_register_response"},
    {TopicKind::sample_unregister_request,
     {"Unregister", "Sample", "Request"},
     3,
     Params::dev_opt_ex,
     "sample_unregister_request"},
    {TopicKind::sample_unregister_response,
     {"Unregister", "Sample", "Response"},
     3,
     Params::dev_opt_ex,
     "sample_unregister_response"},
    {TopicKind::method_control_request, {"Method", "Control", "Request"}, 3, Params::dev_opt_ex, "method_control_request"},
    {TopicKind::method_control_response, {"Method", "Control", "Response"}, 3, Params::dev_opt_ex, "method_control_response"},
    {TopicKind::event_register_request, {"Register", "Event", "Request"}, 3, Params::dev_opt_ex, "event_register_request"},
    {TopicKind::event_register_response, {"Register", "Event", "Response"}, 3, Params::dev_opt_ex, "event_register_response"},
    {TopicKind::event_unregister_request, {"Unregister", "Event", "Request"}, 3, Params::dev_opt_ex, "event_unregister_request"},
    {TopicKind::event_unregister_response,
     {"Unregister", "Event", "Response"},
     3,
     Params::dev_opt_ex,
     "event_unregister_response"},
    {TopicKind::register_request, {"Register", "Request", {}}, 2, Params::none, "register_request"},
    {TopicKind::register_response, {"Register", "Response", {}}, 2, Params::one, "register_response"},
    {TopicKind::discovery_request, {"Discovery", "Request", {}}, 2, Params::ex_only, "discovery_request"},
    {TopicKind::discovery_response, {"Discovery", "Response", {}}, 2, Params::ex_only, "discovery_response"},
    {TopicKind::probe_version, {"Probe", "Version", {}}, 2, Params::one, "probe_version"},
    {TopicKind::query_request, {"Query", "Request", {}}, 2, Params::dev_opt_ex, "query_request"},
    {TopicKind::query_response, {"Query", "Response", {}}, 2, Params::dev_opt_ex, "query_response"},
    {TopicKind::set_request, {"Set", "Request", {}}, 2, Params::dev_opt_ex, "set_request"},
    {TopicKind::set_response, {"Set", "Response", {}}, 2, Params::dev_opt_ex, "set_response"},
    {TopicKind::notify_state, {"Notify", "State", {}}, 2, Params::one, "notify_state"},
    {TopicKind::method_call, {"Method", "Call", {}}, 2, Params::dev_opt_ex, "method_call"},
    {TopicKind::method_status, {"Method", "Status", {}}, 2, Params::dev_opt_ex, "method_status"},
    {TopicKind::method_result, {"Method", "Result", {}}, 2, Params::dev_opt_ex, "method_result"},
    {TopicKind::sample, {"Sample", {}, {}}, 1, Params::dev_channel, "sample"},
    {TopicKind::dynamic_sample, {"Sample", {}, {}}, 1, Params::dev_ex_channel, "dynamic_sample"},
    {TopicKind::event, {"Event", {}, {}}, 1, Params::dev_opt_ex, "event"},
}};

const Shape& shape_of(TopicKind kind) noexcept {
    for (const auto& shape : kShapes)
        if (shape.kind == kind) return shape;
    return kShapes[0];  // unreachable: every kind has a shape
}

bool param_count_fits(Params params, std::size_t count) noexcept {
    switch (params) {
        case Params::none: return count == 0;
        case Params::one:
        case Params::ex_only: return count == 1;
        case Params::dev_opt_ex: return count == 1 || count == 2;
        case Params::dev_channel: return count == 2;
        case Params::dev_ex_channel: return count == 3;
    }
    return false;
}

std::string_view typo_of(std::string_view word) noexcept {
    if (word == "Register") return "Reigster";
    if (word == "Unregister") return "Unreigster";
    return word;
}

std::string join(std::initializer_list<std::string_view> parts) {
    std::size_t size = 0;
    for (auto p : parts) size += p.size() + 1;
    std::string out;
    out.reserve(size);
    for (auto p : parts) {
        if (!out.empty()) out.push_back('/');
        out.append(p);
    }
    return out;
}

std::string build(TopicKind kind, std::string_view dev, std::optional<std::string_view> ex,
                  std::optional<std::string_view> channel, Spelling spelling) {
    const Shape& shape = shape_of(kind);
    std::string out;
    for (std::size_t i = 0; i < shape.prefix_size; ++i) {
        if (i) out.push_back('/');
        out.append(i == 0 && spelling == Spelling::typo ? typo_of(shape.prefix[0]) : shape.prefix[i]);
    }
    auto add = [&](std::string_view segment) {
        out.push_back('/');
        out.append(segment);
    };
    switch (shape.params) {
        case Params::none: break;
        case Params::one: add(dev); break;
        case Params::ex_only: add(ex.value_or(std::string_view())); break;
        case Params::dev_opt_ex:
            add(dev);
            if (ex) add(*ex);
            break;
        case Params::dev_channel:
            add(dev);
            add(channel.value_or(std::string_view()));
            break;
        case Params::dev_ex_channel:
            add(dev);
            add(ex.value_or(std::string_view()));
            add(channel.value_or(std::string_view()));
            break;
    }
    return out;
}

}  // namespace

std::string_view to_string(TopicKind kind) noexcept { return shape_of(kind).name; }

bool has_typo_spelling(TopicKind kind) noexcept {
    const auto first = shape_of(kind).prefix[0];
    return first == "Register" || first == "Unregister";
}

namespace {

// A topic split and matched against the shapes, as views into it: what
// parse_topic() copies into a ParsedTopic and topic_kind() needs no copy of.
struct MatchedTopic {
    const Shape* shape = nullptr;
    Spelling spelling = Spelling::standard;
    const std::string_view* params = nullptr;  // into `segments`
    std::size_t param_count = 0;
    std::array<std::string_view, 7> segments{};  // at most 6 segments exist in any shape
};

bool match_topic(std::string_view topic, MatchedTopic& out) noexcept {
    auto& seg = out.segments;
    std::size_t count = 0;
    std::size_t start = 0;
    while (true) {
        const std::size_t slash = topic.find('/', start);
        const std::string_view part = topic.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
        if (part.empty() || count == seg.size()) return false;
        if (part.find_first_of(std::string_view("+#\0", 3)) != std::string_view::npos) return false;
        seg[count++] = part;
        if (slash == std::string_view::npos) break;
        start = slash + 1;
    }

    out.spelling = Spelling::standard;
    std::string_view first = seg[0];
    if (first == "Reigster") {
        first = "Register";
        out.spelling = Spelling::typo;
    } else if (first == "Unreigster") {
        first = "Unregister";
        out.spelling = Spelling::typo;
    }

    for (const auto& shape : kShapes) {
        if (shape.prefix_size > count || shape.prefix[0] != first) continue;
        bool match = true;
        for (std::size_t i = 1; i < shape.prefix_size; ++i) match = match && shape.prefix[i] == seg[i];
        if (!match) continue;
        const std::size_t params = count - shape.prefix_size;
        if (!param_count_fits(shape.params, params)) continue;
        out.shape = &shape;
        out.params = seg.data() + shape.prefix_size;
        out.param_count = params;
        return true;
    }
    return false;
}

}  // namespace

std::optional<ParsedTopic> parse_topic(std::string_view topic) {
    MatchedTopic m;
    if (!match_topic(topic, m)) return std::nullopt;
    const std::string_view* p = m.params;
    ParsedTopic out;
    out.kind = m.shape->kind;
    out.spelling = m.spelling;
    switch (m.shape->params) {
        case Params::none: break;
        case Params::one: out.dev = std::string(p[0]); break;
        case Params::ex_only: out.ex = std::string(p[0]); break;
        case Params::dev_opt_ex:
            out.dev = std::string(p[0]);
            if (m.param_count == 2) out.ex = std::string(p[1]);
            break;
        case Params::dev_channel:
            out.dev = std::string(p[0]);
            out.channel = std::string(p[1]);
            break;
        case Params::dev_ex_channel:
            out.dev = std::string(p[0]);
            out.ex = std::string(p[1]);
            out.channel = std::string(p[2]);
            break;
    }
    return out;
}

std::optional<TopicKind> topic_kind(std::string_view topic) noexcept {
    MatchedTopic m;
    if (!match_topic(topic, m)) return std::nullopt;
    return m.shape->kind;
}

std::string build_topic(const ParsedTopic& parsed) {
    std::optional<std::string_view> ex;
    std::optional<std::string_view> channel;
    if (parsed.ex) ex = *parsed.ex;
    if (parsed.channel) channel = *parsed.channel;
    const Spelling spelling = has_typo_spelling(parsed.kind) ? parsed.spelling : Spelling::standard;
    return build(parsed.kind, parsed.dev, ex, channel, spelling);
}

std::optional<TopicKind> response_kind(TopicKind request) noexcept {
    switch (request) {
        case TopicKind::register_request: return TopicKind::register_response;
        case TopicKind::discovery_request: return TopicKind::discovery_response;
        case TopicKind::probe_version: return TopicKind::probe_version_response;
        case TopicKind::probe_query_request: return TopicKind::probe_query_response;
        case TopicKind::probe_set_request: return TopicKind::probe_set_response;
        case TopicKind::query_request: return TopicKind::query_response;
        case TopicKind::set_request: return TopicKind::set_response;
        case TopicKind::sample_register_request: return TopicKind::sample_register_response;
        case TopicKind::sample_unregister_request: return TopicKind::sample_unregister_response;
        case TopicKind::method_call: return TopicKind::method_result;
        case TopicKind::method_control_request: return TopicKind::method_control_response;
        case TopicKind::event_register_request: return TopicKind::event_register_response;
        case TopicKind::event_unregister_request: return TopicKind::event_unregister_response;
        default: return std::nullopt;
    }
}

std::optional<std::string> response_topic(const ParsedTopic& request) {
    const auto kind = response_kind(request.kind);
    if (!kind || *kind == TopicKind::register_response) return std::nullopt;
    ParsedTopic response = request;
    response.kind = *kind;
    response.spelling = Spelling::standard;
    response.channel.reset();
    return build_topic(response);
}

std::optional<std::string> response_topic(std::string_view request_topic) {
    const auto parsed = parse_topic(request_topic);
    if (!parsed) return std::nullopt;
    return response_topic(*parsed);
}

std::vector<std::string> response_topics(const ParsedTopic& request, bool standard_typo_topics) {
    std::vector<std::string> out;
    auto topic = response_topic(request);
    if (!topic) return out;
    out.push_back(std::move(*topic));
    const auto kind = *response_kind(request.kind);
    if (standard_typo_topics && has_typo_spelling(kind)) {
        ParsedTopic typo = request;
        typo.kind = kind;
        typo.spelling = Spelling::typo;
        typo.channel.reset();
        out.push_back(build_topic(typo));
    }
    return out;
}

std::vector<std::string> response_topics(std::string_view request_topic, bool standard_typo_topics) {
    const auto parsed = parse_topic(request_topic);
    if (!parsed) return {};
    return response_topics(*parsed, standard_typo_topics);
}

namespace topics {

std::string register_request() { return "Register/Request"; }
std::string register_response(std::string_view cli_uuid) { return join({"Register", "Response", cli_uuid}); }
std::string discovery_request(std::string_view ex) { return join({"Discovery", "Request", ex}); }
std::string discovery_response(std::string_view ex) { return join({"Discovery", "Response", ex}); }
std::string probe_version(std::string_view dev) { return join({"Probe", "Version", dev}); }
std::string probe_version_response(std::string_view dev, OptEx ex) {
    return build(TopicKind::probe_version_response, dev, ex, {}, Spelling::standard);
}
std::string probe_query_request(std::string_view dev, OptEx ex) {
    return build(TopicKind::probe_query_request, dev, ex, {}, Spelling::standard);
}
std::string probe_query_response(std::string_view dev, OptEx ex) {
    return build(TopicKind::probe_query_response, dev, ex, {}, Spelling::standard);
}
std::string probe_set_request(std::string_view dev, OptEx ex) {
    return build(TopicKind::probe_set_request, dev, ex, {}, Spelling::standard);
}
std::string probe_set_response(std::string_view dev, OptEx ex) {
    return build(TopicKind::probe_set_response, dev, ex, {}, Spelling::standard);
}
std::string query_request(std::string_view dev, OptEx ex) {
    return build(TopicKind::query_request, dev, ex, {}, Spelling::standard);
}
std::string query_response(std::string_view dev, OptEx ex) {
    return build(TopicKind::query_response, dev, ex, {}, Spelling::standard);
}
std::string set_request(std::string_view dev, OptEx ex) { return build(TopicKind::set_request, dev, ex, {}, Spelling::standard); }
std::string set_response(std::string_view dev, OptEx ex) {
    return build(TopicKind::set_response, dev, ex, {}, Spelling::standard);
}
std::string sample(std::string_view dev, std::string_view channel) { return join({"Sample", dev, channel}); }
std::string dynamic_sample(std::string_view dev, std::string_view ex, std::string_view channel) {
    return join({"Sample", dev, ex, channel});
}
std::string notify_state(std::string_view tid) { return join({"Notify", "State", tid}); }
std::string sample_register_request(std::string_view dev, OptEx ex, Spelling s) {
    return build(TopicKind::sample_register_request, dev, ex, {}, s);
}
std::string sample_register_response(std::string_view dev, OptEx ex, Spelling s) {
    return build(TopicKind::sample_register_response, dev, ex, {}, s);
}
std::string sample_unregister_request(std::string_view dev, OptEx ex, Spelling s) {
    return build(TopicKind::sample_unregister_request, dev, ex, {}, s);
}
std::string sample_unregister_response(std::string_view dev, OptEx ex, Spelling s) {
    return build(TopicKind::sample_unregister_response, dev, ex, {}, s);
}
std::string method_call(std::string_view dev, OptEx ex) { return build(TopicKind::method_call, dev, ex, {}, Spelling::standard); }
std::string method_status(std::string_view dev, OptEx ex) {
    return build(TopicKind::method_status, dev, ex, {}, Spelling::standard);
}
std::string method_result(std::string_view dev, OptEx ex) {
    return build(TopicKind::method_result, dev, ex, {}, Spelling::standard);
}
std::string method_control_request(std::string_view dev, OptEx ex) {
    return build(TopicKind::method_control_request, dev, ex, {}, Spelling::standard);
}
std::string method_control_response(std::string_view dev, OptEx ex) {
    return build(TopicKind::method_control_response, dev, ex, {}, Spelling::standard);
}
std::string event_register_request(std::string_view dev, OptEx ex, Spelling s) {
    return build(TopicKind::event_register_request, dev, ex, {}, s);
}
std::string event_register_response(std::string_view dev, OptEx ex, Spelling s) {
    return build(TopicKind::event_register_response, dev, ex, {}, s);
}
std::string event_unregister_request(std::string_view dev, OptEx ex, Spelling s) {
    return build(TopicKind::event_unregister_request, dev, ex, {}, s);
}
std::string event_unregister_response(std::string_view dev, OptEx ex, Spelling s) {
    return build(TopicKind::event_unregister_response, dev, ex, {}, s);
}
std::string event(std::string_view dev, OptEx ex) { return build(TopicKind::event, dev, ex, {}, Spelling::standard); }

std::vector<std::string> adapter_subscriptions(std::string_view dev) {
    std::vector<std::string> out;
    out.push_back(register_response(dev));
    auto both = [&](TopicKind kind, Spelling spelling) {
        const std::string base = build(kind, dev, std::nullopt, {}, spelling);
        out.push_back(base);
        out.push_back(base + "/+");
    };
    for (TopicKind kind :
         {TopicKind::probe_version_response, TopicKind::probe_query_request, TopicKind::probe_set_request,
          TopicKind::query_request, TopicKind::set_request, TopicKind::method_call, TopicKind::method_control_request})
        both(kind, Spelling::standard);
    for (TopicKind kind : {TopicKind::sample_register_request, TopicKind::sample_unregister_request,
                           TopicKind::event_register_request, TopicKind::event_unregister_request}) {
        both(kind, Spelling::standard);
        both(kind, Spelling::typo);
    }
    return out;
}

// Released in 0.1.0 and no longer part of the API: it listed four filters
// while the agent subscribes to the requests it answers and the states and
// responses it observes (src/agent/agent.cpp, answer_filters() and
// observe_filters()). Still exported so a program built against 0.1.0 keeps
// loading (docs/building.md, "ABI check"); delete it with the next SONAME bump.
NCLINK_API std::vector<std::string> agent_subscriptions();
std::vector<std::string> agent_subscriptions() {
    return {"Register/Request", "Discovery/Request/+", "Probe/Version/+", "Notify/State/+"};
}

}  // namespace topics
}  // namespace nclink
