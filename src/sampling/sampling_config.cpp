#include <nclink/adapter_config.hpp>

#include "core/config_reader.hpp"

namespace nclink::detail {

Result<void> read_sampling_config(const Json& section, SamplingConfig& out) {
    if (!section.is_object()) return make_error(ErrorCode::value_type, "configuration: sampling must be an object");
    ConfigReader r(section, "sampling.");
    NCLINK_TRY(r.boolean("enabled", out.enabled));
    NCLINK_TRY(r.count("max_dynamic_channels", out.max_dynamic_channels));
    return r.no_unknown_keys();
}

}  // namespace nclink::detail
