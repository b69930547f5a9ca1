#include "mtconnect/agent_source.hpp"

#include "mtconnect/probe_document.hpp"
#include "mtconnect/streams_document.hpp"

#include <httplib.h>

#include <algorithm>
#include <memory>

namespace nclink::mtconnect {

Result<AgentUrl> parse_agent_url(const std::string& url) {
    const std::string scheme = "http://";
    if (url.compare(0, scheme.size(), scheme) != 0)
        return make_error(ErrorCode::syntax_error, "agent URL '" + url + "': only http:// agents are read");
    std::string rest = url.substr(scheme.size());
    AgentUrl out;
    const std::size_t slash = rest.find('/');
    if (slash != std::string::npos) {
        out.prefix = rest.substr(slash);
        rest = rest.substr(0, slash);
        while (!out.prefix.empty() && out.prefix.back() == '/') out.prefix.pop_back();
    }
    const std::size_t bracket = rest.find(']');
    const std::size_t colon = rest.rfind(':');
    if (colon != std::string::npos && (bracket == std::string::npos ? rest.find(':') == colon : colon > bracket)) {
        const std::string port = rest.substr(colon + 1);
        if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos || std::stoi(port) < 1 ||
            std::stoi(port) > 65535)
            return make_error(ErrorCode::syntax_error, "agent URL '" + url + "': bad port '" + port + "'");
        out.port = std::stoi(port);
        rest = rest.substr(0, colon);
    }
    if (rest.size() > 2 && rest.front() == '[' && rest.back() == ']') rest = rest.substr(1, rest.size() - 2);
    if (rest.empty()) return make_error(ErrorCode::syntax_error, "agent URL '" + url + "': no host");
    out.host = rest;
    return out;
}

AgentSource::AgentSource(AgentOptions options, LiveValues& values, SourceStatus& status, Logger logger)
    : options_(std::move(options)), values_(values), status_(status), logger_(std::move(logger)) {}

AgentSource::~AgentSource() { stop(); }

Result<std::string> AgentSource::get(const std::string& path) const { return agent_get(url_, path, options_.timeout); }

Result<std::string> agent_get(const AgentUrl& url_, const std::string& path, std::chrono::milliseconds t) {
    httplib::Client client(url_.host, url_.port);
    client.set_connection_timeout(std::chrono::duration_cast<std::chrono::seconds>(t).count(),
                                  static_cast<long>((t.count() % 1000) * 1000));
    client.set_read_timeout(std::chrono::duration_cast<std::chrono::seconds>(t).count(),
                            static_cast<long>((t.count() % 1000) * 1000));
    const std::string target = url_.prefix + path;
    const std::string where = "http://" + url_.host + ":" + std::to_string(url_.port) + target;
    auto res = client.Get(target.c_str());
    if (!res) return make_error(ErrorCode::unavailable, "GET " + where + ": " + httplib::to_string(res.error()));
    // MTConnect agents answer errors with an Error document and a 4xx status
    // (part 1, 8.4): the caller reads it. Anything else is the HTTP error.
    if (res->status != 200 && res->body.find("MTConnectError") == std::string::npos)
        return make_error(ErrorCode::unavailable, "GET " + where + ": HTTP " + std::to_string(res->status));
    return std::move(res->body);
}

Result<ReverseModel> AgentSource::read_model() const {
    auto body = get("/probe");
    if (!body.ok()) return std::move(body).error();
    auto probe = read_probe(body.value());
    if (!probe.ok()) return std::move(probe).error();
    ReverseOptions o;
    o.device = options_.device;
    return reverse_map(probe.value(), o);
}

Result<void> AgentSource::start() {
    auto url = parse_agent_url(options_.url);
    if (!url.ok()) return std::move(url).error();
    url_ = std::move(url).value();
    auto model = read_model();
    if (!model.ok()) return std::move(model).error();
    // The probe's instance: a restart before the first /current is seen too.
    instance_ = model->instance_id;
    values_.install(std::make_shared<const ReverseModel>(std::move(model).value()));
    status_.count([](SourceCounters& c) { ++c.probes; });
    {
        std::lock_guard lock(mutex_);
        stopping_ = false;
    }
    need_probe_ = false;
    need_current_ = true;
    thread_ = std::thread([this] { run(); });
    return ok_result();
}

void AgentSource::stop() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void AgentSource::wait(std::chrono::milliseconds how_long) {
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, how_long, [&] { return stopping_; });
}

void AgentSource::run() {
    for (;;) {
        {
            std::lock_guard lock(mutex_);
            if (stopping_) return;
        }
        bool more = false;
        const bool ok = [&] {
            try {
                const std::uint64_t before = next_;
                const bool stepped = step();
                // A /sample that came back full: the agent has more, ask again now.
                more = stepped && !need_current_ && !need_probe_ && next_ - before >= options_.count;
                return stepped;
            } catch (const std::exception& e) {  // never let the thread die: say why and retry
                status_.disconnected(std::string("MTConnect source: ") + e.what());
                return false;
            }
        }();
        if (!ok) {
            status_.count([](SourceCounters& c) { ++c.failures; });
            wait(options_.retry);
        } else if (!more) {
            wait(options_.interval);
        }
    }
}

bool AgentSource::step() {
    if (need_probe_) {
        auto model = read_model();
        if (!model.ok()) {
            status_.disconnected(model.error().message);
            logger_.warn("MTConnect source: {}", model.error().message);
            return false;
        }
        instance_ = model->instance_id;
        values_.install(std::make_shared<const ReverseModel>(std::move(model).value()));
        status_.count([](SourceCounters& c) { ++c.probes; });
        need_probe_ = false;
        need_current_ = true;
    }
    const bool current = need_current_;
    auto body =
        current ? get("/current") : get("/sample?from=" + std::to_string(next_) + "&count=" + std::to_string(options_.count));
    if (!body.ok()) {
        status_.disconnected(body.error().message);
        logger_.debug("MTConnect source: {}", body.error().message);
        need_current_ = true;  // what came meanwhile is unknown: start from the whole state again
        return false;
    }
    auto reply = read_streams(body.value());
    if (!reply.ok()) {
        status_.disconnected("the agent's answer is not usable: " + reply.error().message);
        logger_.warn("MTConnect source: {}", reply.error().message);
        need_current_ = true;
        return false;
    }
    if (reply->is_error()) {
        const auto& codes = reply->error_codes;
        if (!current && std::find(codes.begin(), codes.end(), "OUT_OF_RANGE") != codes.end()) {
            // `from` fell out of the agent's buffer: observations were lost;
            // /current is the whole state again (part 1, 8.3.4).
            logger_.info("MTConnect source: sample from {} is out of the agent's buffer ({}); reading /current", next_,
                         reply->error_text);
            status_.count([](SourceCounters& c) { ++c.out_of_range; });
            need_current_ = true;
            return true;
        }
        status_.disconnected("the agent answered an error: " + reply->error_text);
        logger_.warn("MTConnect source: the agent answered {}", reply->error_text);
        need_current_ = true;
        return false;
    }
    const StreamsDocument& doc = reply->streams;
    if (!instance_.empty() && doc.instance_id != instance_) {
        // A restarted agent: its sequence numbers start again and its device
        // may have changed. Probe, then the whole state.
        logger_.info("MTConnect source: the agent restarted (instanceId {} -> {}); reading /probe and /current", instance_,
                     doc.instance_id);
        status_.count([](SourceCounters& c) { ++c.restarts; });
        instance_ = doc.instance_id;
        need_probe_ = true;
        need_current_ = true;
        return true;
    }
    instance_ = doc.instance_id;
    if (current) values_.reset();
    std::uint64_t used = 0;
    for (const auto& o : doc.observations) used += values_.apply(o) ? 1 : 0;
    next_ = doc.next_sequence;
    need_current_ = false;
    status_.count([&](SourceCounters& c) {
        ++(current ? c.currents : c.samples);
        c.observations += used;
    });
    if (values_.available() == std::optional<bool>(false))
        status_.disconnected("the MTConnect agent reports the device UNAVAILABLE");
    else status_.connected();
    return true;
}

}  // namespace nclink::mtconnect
