// Follows an MTConnect agent over HTTP (MTConnect 1.4 part 1, 8): /probe,
// then /current, then /sample?from=<nextSequence>&count=<count> every
// `interval`, applying every observation to LiveValues in sequence order.
//
// Recovery (docs/gateway.md "MTConnect and SHDR sources"):
//  - a changed Header@instanceId (the agent restarted: its sequence numbers
//    start again) -> /probe again (the device may have changed), then /current;
//  - /sample answered OUT_OF_RANGE (`from` fell out of the agent's buffer:
//    observations were lost) -> /current again, which is the whole state;
//  - a failed request (connection refused or dropped, timeout, an HTTP
//    status, a document that is not MTConnect) -> link() disconnected with
//    the reason, retried every `retry`; then /current again (values kept
//    from before would be stale), or /probe when none was read yet.
//  - a /sample that came back full (count observations) is followed at once
//    by the next one, so a busy agent is not followed at interval pace.
//
// Threading: one thread of its own (start()/stop() from the driver's
// open()/close()); it writes LiveValues and SourceStatus, both thread-safe.
#pragma once

#include "mtconnect/live_values.hpp"
#include "mtconnect/source_status.hpp"

#include <nclink/log.hpp>
#include <nclink/result.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace nclink::mtconnect {

struct AgentOptions {
    std::string url;     ///< "http://host:port[/prefix]"
    std::string device;  ///< uuid, name or id of the Device ("" = the first)
    std::chrono::milliseconds interval{500};
    std::chrono::milliseconds retry{1000};
    std::chrono::milliseconds timeout{3000};  ///< connect and read timeout of each request
    std::uint32_t count = 1000;               ///< /sample count
};

/// "http://host:port/prefix" -> host, port, prefix. Errors (412) for other schemes, no host, a bad port.
struct AgentUrl {
    std::string host;
    int port = 80;
    std::string prefix;  ///< "" or "/agent"
};
Result<AgentUrl> parse_agent_url(const std::string& url);

/// One GET of an agent: the body of a 200, or an error (202) naming the URL
/// and what happened (connection refused, timeout, an HTTP status). Non-200
/// answers that are MTConnect Error documents are returned as bodies (the
/// document says what went wrong).
Result<std::string> agent_get(const AgentUrl& url, const std::string& path_and_query, std::chrono::milliseconds timeout);

class AgentSource {
public:
    AgentSource(AgentOptions options, LiveValues& values, SourceStatus& status, Logger logger);
    ~AgentSource();  ///< stop()s
    AgentSource(const AgentSource&) = delete;
    AgentSource& operator=(const AgentSource&) = delete;

    /// Reads the probe once (so open() fails with a clear error when the
    /// agent is absent or its probe is not usable: the model must come from
    /// somewhere), then follows the agent on its own thread.
    Result<void> start();
    void stop();

    /// agent_get() on the configured agent.
    Result<std::string> get(const std::string& path_and_query) const;
    /// /probe, read and mapped.
    Result<ReverseModel> read_model() const;

private:
    void run();
    bool step();  ///< one request; false: wait `retry`
    void wait(std::chrono::milliseconds how_long);

    AgentOptions options_;
    AgentUrl url_;
    LiveValues& values_;
    SourceStatus& status_;
    Logger logger_;
    std::string instance_;
    std::uint64_t next_ = 0;
    bool need_probe_ = false;
    bool need_current_ = true;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stopping_ = false;
    std::thread thread_;
};

}  // namespace nclink::mtconnect
