// Fuzz target of the model engine: arbitrary bytes through parse, validate,
// index and serialize. Must never crash, throw or trip a sanitizer.
#include <nclink/model.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const nclink::LoadResult result = nclink::parse_model(text);
    for (const auto& p : result.problems)
        if (p.message.empty()) std::abort();  // every problem explains itself
    if (!result.model) return 0;
    const nclink::Model& model = *result.model;

    // Exercise the index the way an adapter does.
    for (const auto& info : model.objects()) {
        if (model.find(info.id) != &info) std::abort();
        (void)model.owning_device(info.id);
        (void)model.ids_at_path(info.path);
    }
    for (const auto& channel : model.channels()) (void)model.channel_items(channel.id);
    for (const auto& device : model.devices()) (void)nclink::resolve_dev_uuid(device);

    // Serialization is a fixed point: what we write reads back as the same model.
    const std::string text2 = nclink::serialize_model(model);
    const nclink::LoadResult again = nclink::parse_model(text2);
    if (!again.model || !(*again.model == model)) std::abort();
    return 0;
}
