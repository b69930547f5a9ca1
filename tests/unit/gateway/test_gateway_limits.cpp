// A gateway of many machines needs more open files than Debian's soft
// default of 1024 (libmosquitto holds three descriptors a connection): it
// raises the soft limit to what its machines need, never above the hard one.
#include <nclink/gateway.hpp>

#include <catch2/catch.hpp>

#include <sys/resource.h>

using namespace nclink;

TEST_CASE("gateway: the soft open-file limit is raised to what the machines need within the hard limit") {
    rlimit original{};
    REQUIRE(::getrlimit(RLIMIT_NOFILE, &original) == 0);
    if (original.rlim_max != RLIM_INFINITY && original.rlim_max < 4096) {
        WARN("hard open-file limit " << original.rlim_max << ": too low to test raising the soft one");
        return;
    }
    rlimit low = original;
    low.rlim_cur = 200;  // below what even one machine asks for (256 + 8 a machine)
    REQUIRE(::setrlimit(RLIMIT_NOFILE, &low) == 0);

    const auto machines = [](int n) {
        GatewayConfig config;
        for (int i = 0; i < n; ++i) {
            MachineConfig m;
            m.id = "m" + std::to_string(i);
            m.adapter.model_path = "/nonexistent/model.json";  // refused at start: only the limit matters here
            config.machines.push_back(m);
        }
        return config;
    };
    const auto soft = [] {
        rlimit now{};
        REQUIRE(::getrlimit(RLIMIT_NOFILE, &now) == 0);
        return now.rlim_cur;
    };
    SECTION("at start") {
        Gateway gateway(machines(100));
        (void)gateway.start();           // every machine refused (no model): named in the error
        CHECK(soft() == 256 + 8 * 100);  // raised to the need, not to the hard limit
    }
    SECTION("when a reload brings more machines than the gateway started with") {
        Gateway gateway(machines(0));
        REQUIRE(gateway.start());
        CHECK(soft() == 256);
        const GatewayReload report = gateway.reload(machines(150));
        CHECK(report.errors.size() == 150);  // no model: refused, but only after the limit was raised
        CHECK(soft() == 256 + 8 * 150);
    }
    rlimit now{};
    REQUIRE(::getrlimit(RLIMIT_NOFILE, &now) == 0);
    CHECK(now.rlim_max == original.rlim_max);
    REQUIRE(::setrlimit(RLIMIT_NOFILE, &original) == 0);
}
