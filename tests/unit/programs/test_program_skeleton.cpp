#include "program.hpp"

#include <catch2/catch.hpp>

#include <mutex>
#include <utility>

using namespace nclink;
using namespace nclink::program;
using namespace std::chrono_literals;

namespace {

struct Captured {
    std::mutex mutex;
    std::vector<std::pair<LogLevel, std::string>> lines;
    Logger logger() {
        return Logger([this](LogLevel level, std::string_view message) {
            std::lock_guard<std::mutex> lock(mutex);
            lines.emplace_back(level, std::string(message));
        });
    }
};

struct Argv {
    explicit Argv(std::vector<std::string> words) : storage(std::move(words)) {
        for (auto& w : storage) pointers.push_back(w.data());
    }
    int argc() const { return static_cast<int>(pointers.size()); }
    char** argv() { return pointers.data(); }
    std::vector<std::string> storage;
    std::vector<char*> pointers;
};

}  // namespace

TEST_CASE("arguments are read front to back, options with their values") {
    Argv line({"prog", "--broker", "tcp://h:1", "--check", "--config", "a.json"});
    std::optional<std::string> broker;
    std::string config;
    bool check = false;
    std::vector<std::string> unknown;
    for (Arguments args(line.argc(), line.argv()); args.next();) {
        if (args.is("--broker")) REQUIRE(args.value(broker));
        else if (args.is("--config")) REQUIRE(args.value(config));
        else if (args.is("--check")) check = true;
        else unknown.push_back(args.current());
    }
    CHECK(broker == std::optional<std::string>("tcp://h:1"));
    CHECK(config == "a.json");
    CHECK(check);
    CHECK(unknown.empty());
}

TEST_CASE("an option at the end without its value is refused and changes nothing") {
    Argv line({"prog", "--broker"});
    Arguments args(line.argc(), line.argv());
    REQUIRE(args.next());
    CHECK(args.is("--broker"));
    CHECK_FALSE(args.has_value());
    std::optional<std::string> broker;
    CHECK_FALSE(args.value(broker));
    CHECK_FALSE(broker);
    CHECK_FALSE(args.next());
}

TEST_CASE("-h and --help ask for help, nothing else does") {
    for (const char* word : {"-h", "--help"}) {
        Argv line({"prog", word});
        Arguments args(line.argc(), line.argv());
        REQUIRE(args.next());
        CHECK(args.help());
    }
    Argv line({"prog", "--helpful"});
    Arguments args(line.argc(), line.argv());
    REQUIRE(args.next());
    CHECK_FALSE(args.help());
}

TEST_CASE("the reload report says what applied, what waits for a restart, or nothing") {
    Captured out;
    const Logger logger = out.logger();
    log_reload(logger, "prog", "a.json", ConfigReload{});
    log_reload(logger, "prog", "a.json", ConfigReload{{"log_level", "access"}, {}});
    log_reload(logger, "prog", "a.json", ConfigReload{{}, {"broker.url", "broker.tls"}});
    log_reload(logger, "prog", "a.json", ConfigReload{{"log_level"}, {"tick_ms"}});
    log_nothing_to_reload(logger, "prog");
    log_reload_refused(logger, "prog", "a.json:3:1: syntax error");
    const std::vector<std::pair<LogLevel, std::string>> expected = {
        {LogLevel::info, "prog: reloaded a.json: nothing changed"},
        {LogLevel::info, "prog: reloaded a.json: applied log_level, access"},
        {LogLevel::warn, "prog: changed in a.json but applied only after a restart: broker.url, broker.tls"},
        {LogLevel::info, "prog: reloaded a.json: applied log_level"},
        {LogLevel::warn, "prog: changed in a.json but applied only after a restart: tick_ms"},
        {LogLevel::warn, "prog: SIGHUP: no --config file to reload"},
        {LogLevel::error, "prog: reload refused, the running configuration stays: a.json:3:1: syntax error"},
    };
    CHECK(out.lines == expected);
    CHECK(joined({}).empty());
    CHECK(joined({"a"}) == "a");
}

TEST_CASE("a broker that refuses is reported at once, a connection ends the wait") {
    TransportStats refused;
    refused.refused = true;
    refused.last_error = "the broker refused the user name or password";
    int calls = 0;
    CHECK(refused_by_broker([&] {
              ++calls;
              return refused;
          }) == std::optional<std::string>("the broker refused the user name or password"));
    CHECK(calls == 1);

    TransportStats connected;
    connected.connects = 1;
    CHECK_FALSE(refused_by_broker([&] { return connected; }));

    // Neither within the patience: an unreachable broker is waited for, not an error.
    CHECK_FALSE(refused_by_broker([&] { return TransportStats{}; }, 100ms));
}

TEST_CASE("SIGHUP reloads and SIGTERM ends serving, each on the waiting thread") {
    sigset_t before;
    pthread_sigmask(SIG_SETMASK, nullptr, &before);
    {
        const Signals signals;
        // Blocked now: raised here, the signals wait for serve() to take them.
        ::raise(SIGHUP);
        int reloads = 0;
        std::thread::id reloaded_on;
        const auto serving = std::this_thread::get_id();
        const int stopped_by = signals.serve([&] {
            ++reloads;
            reloaded_on = std::this_thread::get_id();
            if (reloads == 1) ::raise(SIGTERM);
        });
        CHECK(reloads == 1);
        CHECK(reloaded_on == serving);
        CHECK(stopped_by == SIGTERM);
        CHECK(std::string(Signals::name(stopped_by)) == "SIGTERM");
        CHECK(std::string(Signals::name(SIGINT)) == "SIGINT");
    }
    pthread_sigmask(SIG_SETMASK, &before, nullptr);
}
