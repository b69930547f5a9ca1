// The sample path allocates nothing per row once it runs steadily: the
// sampler's typed reads go straight into the ring, and the uploader's
// batch, encoder buffer and checks reuse what they grew to. A DTU costs a
// few allocations (its message), however many rows it carries.
//
// Counted by support/counting_new.hpp (a counter in front of malloc).
#include "engine_fixture.hpp"
#include "support/counting_new.hpp"

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

// A firmware-style driver: typed values, no Json.
class TypedDriver final : public Driver {
public:
    DriverInfo info() const override { return {"typed", "1", true}; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        for (std::size_t i = 0; i < points.size(); ++i) results[i] = Json(1.5);
    }
    bool read_samples(const std::vector<PointRef>& points, SampleValue* out) override {
        ++reads;
        for (std::size_t i = 0; i < points.size(); ++i)
            out[i] = SampleValue::float64(100.125 + static_cast<double>(reads % 7) + i);
        return true;
    }
    std::uint64_t reads = 0;
};

/// Allocations (operator new) made by `work`, on any thread.
template <class Work>
std::uint64_t allocations_of(Work work) {
    g_allocations.store(0);
    g_counting.store(true);
    work();
    g_counting.store(false);
    return g_allocations.load();
}

struct Steady {
    std::uint64_t rows = 0;                  // sampled in the measured upload period
    std::uint64_t sampling_allocations = 0;  // while sampling them
    std::uint64_t upload_allocations = 0;    // while publishing them as one DTU
};

/// One channel of 50 typed points at 1 ms, uploaded every `upload`: after
/// three periods of warm-up (the ring, the uploader's batch and the
/// encoder's buffer reach their steady size), what one more period costs.
Steady measure(std::chrono::milliseconds upload) {
    auto driver = std::make_shared<TypedDriver>();
    EngineFixture f({}, false, driver);
    std::vector<std::string> ids;
    for (int i = 0; i < 50; ++i) ids.push_back("p" + std::to_string(i));
    REQUIRE(f.engine->add_channel(EngineFixture::spec("c", ids, 1, static_cast<double>(upload.count()))).ok());
    f.sent.reserve(64);  // the test's own sink must not be what allocates
    for (int i = 0; i < 3; ++i) {
        f.step(1ms, upload);
        f.engine->run_upload_once();
    }
    Steady out;
    const auto rows_before = f.stats("c").rows_sampled;
    out.sampling_allocations = allocations_of([&] { f.step(1ms, upload); });
    out.rows = f.stats("c").rows_sampled - rows_before;
    const auto dtus_before = f.stats("c").dtus_published;
    out.upload_allocations = allocations_of([&] { f.engine->run_upload_once(); });
    REQUIRE(f.stats("c").dtus_published == dtus_before + 1);
    return out;
}

}  // namespace

TEST_CASE("steady sampling allocates nothing per row, and a DTU the same few times whatever its rows") {
    if (!NCLINK_TEST_COUNTS_ALLOCATIONS) {
        WARN("sanitizer build: allocations are not counted");
        return;
    }
    const Steady short_dtu = measure(100ms);
    const Steady long_dtu = measure(400ms);
    CHECK(short_dtu.rows == 100);
    CHECK(long_dtu.rows == 400);
    CHECK(short_dtu.sampling_allocations == 0);
    CHECK(long_dtu.sampling_allocations == 0);
    // The DTU's message (its payload and topic) and nothing per row.
    CHECK(short_dtu.upload_allocations <= 3);
    CHECK(long_dtu.upload_allocations == short_dtu.upload_allocations);
}
