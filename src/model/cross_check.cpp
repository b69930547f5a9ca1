// Cross-object checks run after the whole tree has been read.
#include "model/cross_check.hpp"

#include "model/problems.hpp"

#include <nclink/value_rules.hpp>

#include <fmt/format.h>

namespace nclink::model_detail {

void check_channel_references(const Model& model, const std::vector<ChannelReference>& refs, Problems& problems) {
    for (const auto& ref : refs) {
        const ObjectInfo* target = model.find(ref.id);
        if (target == nullptr) {
            problems.fatal(ref.pointer, fmt::format("sample channel \"{}\" names \"{}\", which is "
                                                    "not a data item of this model",
                                                    ref.channel_id, ref.id));
        } else if (target->kind == ObjectKind::config_item) {
            problems.conformance(ref.pointer, fmt::format("sample channel \"{}\" samples config object \"{}\" "
                                                          "(6.2.2 note b: config objects are not sample "
                                                          "sources)",
                                                          ref.channel_id, ref.id));
        } else if (target->kind != ObjectKind::data_item) {
            problems.fatal(ref.pointer, fmt::format("sample channel \"{}\" names \"{}\", which is "
                                                    "a {}, not a data item",
                                                    ref.channel_id, ref.id, to_string(target->kind)));
        }
    }
}

void check_fixed_values(const Model& model, Problems& problems) {
    const ValueRules rules(model);
    for (const auto& object : model.data_objects()) {
        if (!object.value) continue;
        const ValueRule* rule = rules.find(object.id);
        if (rule == nullptr) continue;
        if (rule->check(*object.value) == ValueFault::kind) continue;  // the reader reported it
        auto verdict = rule->verify(*object.value);
        if (verdict) continue;
        const ObjectInfo* info = model.find(object.id);
        problems.conformance(pointer_append(info ? info->pointer : std::string(), "value"),
                             fmt::format("the fixed value breaks chapter 7: {}", verdict.error().message));
    }
}

}  // namespace nclink::model_detail
