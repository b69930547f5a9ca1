#include "sampling/spool_extension.hpp"

#include "sampling/sample_spool.hpp"

#include <filesystem>

namespace nclink::sampling_detail {
namespace {

SpoolOptions spool_options(const feature_detail::FeatureHost& host, const SamplingConfig& config) {
    SpoolOptions o;
    o.memory_bytes = config.spool_memory_bytes;
    o.disk_bytes = config.spool_disk_bytes;
    if (o.disk_bytes > 0 && !host.persistence_dir.empty())
        o.disk_dir = (std::filesystem::path(host.persistence_dir) / "sample-spool").string();
    else if (o.disk_bytes > 0)
        host.logger.warn("sampling.spool_disk_bytes is set but persistence_dir is not: spooling to RAM only");
    return o;
}

class SpoolExtension final : public SamplingExtension {
public:
    SpoolExtension(feature_detail::FeatureHost& host, SamplingService& service)
        : engine_(service.engine()),
          spool_(std::make_shared<SampleSpool>(spool_options(host, service.config()), host.transport, host.logger, host.work)) {
        // The sink holds the spool: the engine may flush into it until it is
        // destroyed, whatever the order members go in.
        service.wrap_sink([spool = spool_](DtuSink) { return DtuSink([spool](Message m) { spool->publish(std::move(m)); }); });
    }

    std::string_view name() const override { return "spool"; }
    Result<void> start() override { return spool_->start(); }
    void stop() override {
        // Extensions stop before the engine, but the engine's last rows must
        // still reach the spool: stop the engine (idempotent) first.
        engine_.stop();
        spool_->stop();
    }
    void on_link(LinkState link) override { spool_->on_link(link); }
    Json stats() const override { return to_json(spool_->stats()); }
    void add_drops(feature_detail::DropCounts& out) const override { out.add("sample_spool_full", spool_->stats().dropped); }

private:
    SamplingEngine& engine_;
    std::shared_ptr<SampleSpool> spool_;
};

}  // namespace

std::unique_ptr<SamplingExtension> make_spool_extension(feature_detail::FeatureHost& host, SamplingService& service) {
    return std::make_unique<SpoolExtension>(host, service);
}

}  // namespace nclink::sampling_detail
