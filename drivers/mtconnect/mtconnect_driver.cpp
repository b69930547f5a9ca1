#include "mtconnect/mtconnect_driver.hpp"

#include "mtconnect/agent_source.hpp"
#include "mtconnect/shdr_source.hpp"

#include <set>

namespace nclink::mtconnect {

namespace {

Error config_error(const std::string& key, const std::string& what, ErrorCode code = ErrorCode::value_type) {
    return make_error(code, "mtconnect driver configuration: " + key + ": " + what);
}

Result<std::chrono::milliseconds> millis(const Json& j, const char* key, int min, int max) {
    if (!j.is_number_integer() || j.get<long long>() < min || j.get<long long>() > max)
        return config_error(key, "must be a whole number of milliseconds in " + std::to_string(min) + ".." + std::to_string(max));
    return std::chrono::milliseconds(j.get<long long>());
}

Result<std::string> text(const Json& j, const char* key) {
    if (!j.is_string() || j.get<std::string>().empty()) return config_error(key, "must be a non-empty string");
    return j.get<std::string>();
}

}  // namespace

Result<DriverConfig> parse_driver_config(const Json& json) {
    if (!json.is_object())
        return config_error("/", R"(must be an object with "agent": "http://host:port" or "shdr": "host:port")",
                            ErrorCode::parameter_missing);
    static const std::set<std::string> known = {"agent",    "shdr",       "probe_file", "device", "interval_ms",
                                                "retry_ms", "timeout_ms", "ping_ms",    "count"};
    for (const auto& [key, value] : json.items())
        if (!known.count(key)) return config_error(key, "unknown key", ErrorCode::keys_of_arguments);
    DriverConfig c;
    for (auto [key, field] : {std::pair{"agent", &c.agent}, std::pair{"shdr", &c.shdr}, std::pair{"probe_file", &c.probe_file},
                              std::pair{"device", &c.device}}) {
        if (!json.contains(key)) continue;
        auto v = text(json[key], key);
        if (!v.ok()) return std::move(v).error();
        *field = std::move(v).value();
    }
    for (auto [key, field, min] : {std::tuple{"interval_ms", &c.interval, 1}, std::tuple{"retry_ms", &c.retry, 1},
                                   std::tuple{"timeout_ms", &c.timeout, 1}, std::tuple{"ping_ms", &c.ping, 100}}) {
        if (!json.contains(key)) continue;
        auto v = millis(json[key], key, min, 3600000);
        if (!v.ok()) return std::move(v).error();
        *field = v.value();
    }
    if (json.contains("count")) {
        const Json& n = json["count"];
        if (!n.is_number_integer() || n.get<long long>() < 1 || n.get<long long>() > 1000000)
            return config_error("count", "must be a whole number in 1..1000000");
        c.count = static_cast<std::uint32_t>(n.get<long long>());
    }
    if (c.agent.empty() == c.shdr.empty())
        return config_error("/", R"(name exactly one source: "agent" (an MTConnect agent) or "shdr" (an SHDR adapter))",
                            ErrorCode::parameter_missing);
    if (!c.shdr.empty() && c.probe_file.empty())
        return config_error("probe_file", "an SHDR source needs the Devices document that describes its keys",
                            ErrorCode::parameter_missing);
    return c;
}

MtConnectDriver::MtConnectDriver(std::optional<DriverConfig> config) : config_(std::move(config)) {}

MtConnectDriver::~MtConnectDriver() { close(); }

DriverInfo MtConnectDriver::info() const { return DriverInfo{"mtconnect", "1.0", true}; }

Result<void> MtConnectDriver::open(const DriverContext& context) {
    logger_ = context.logger;
    if (!config_) {
        auto parsed = parse_driver_config(context.config);
        if (!parsed.ok()) return std::move(parsed).error();
        config_ = std::move(parsed).value();
    }
    const DriverConfig& c = *config_;
    if (!c.agent.empty()) {
        AgentOptions o;
        o.url = c.agent;
        o.device = c.device;
        o.interval = c.interval;
        o.retry = c.retry;
        o.timeout = c.timeout;
        o.count = c.count;
        agent_ = std::make_unique<AgentSource>(std::move(o), values_, status_, logger_);
        if (auto started = agent_->start(); !started) {
            agent_.reset();
            return started;
        }
        return ok_result();
    }
    ShdrOptions o;
    o.address = c.shdr;
    o.probe_file = c.probe_file;
    o.device = c.device;
    o.retry = c.retry;
    o.timeout = c.timeout;
    o.ping = c.ping;
    shdr_ = std::make_unique<ShdrSource>(std::move(o), values_, status_, logger_);
    if (auto started = shdr_->start(); !started) {
        shdr_.reset();
        return started;
    }
    return ok_result();
}

void MtConnectDriver::close() {
    if (agent_) agent_->stop();
    if (shdr_) shdr_->stop();
    agent_.reset();
    shdr_.reset();
}

void MtConnectDriver::read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) {
    for (std::size_t i = 0; i < points.size(); ++i) {
        const std::optional<Json> v = values_.get(points[i].id);
        if (!v) results[i] = make_error(ErrorCode::unavailable, points[i].id + ": the MTConnect probe has no such item");
        else if (v->is_null()) results[i] = make_error(ErrorCode::unavailable, points[i].id + ": UNAVAILABLE in MTConnect");
        else results[i] = *v;
    }
}

Result<void> MtConnectDriver::write(const WriteRequest& request) {
    // MTConnect agents and adapters are read-only (MTConnect 1.4 part 1, 5:
    // an agent answers requests for data; nothing is written back).
    return make_error(ErrorCode::permission_denied, request.id + ": the machine is read through MTConnect, which is read-only");
}

MachineLinkStatus MtConnectDriver::link() const { return status_.link(); }

}  // namespace nclink::mtconnect
