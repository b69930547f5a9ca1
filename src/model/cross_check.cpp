// Cross-object checks run after the whole tree has been read.
#include "model/cross_check.hpp"

#include <fmt/format.h>

namespace nclink::model_detail {

void check_channel_references(const Model& model, const std::vector<ChannelReference>& refs,
                              Problems& problems) {
    for (const auto& ref : refs) {
        const ObjectInfo* target = model.find(ref.id);
        if (target == nullptr) {
            problems.fatal(ref.pointer, fmt::format("sample channel \"{}\" names \"{}\", which is "
                                                    "not a data item of this model",
                                                    ref.channel_id, ref.id));
        } else if (target->kind == ObjectKind::config_item) {
            problems.conformance(ref.pointer,
                                 fmt::format("sample channel \"{}\" samples config object \"{}\" "
                                             "(6.2.2 note b: config objects are not sample "
                                             "sources)", ref.channel_id, ref.id));
        } else if (target->kind != ObjectKind::data_item) {
            problems.fatal(ref.pointer, fmt::format("sample channel \"{}\" names \"{}\", which is "
                                                    "a {}, not a data item", ref.channel_id,
                                                    ref.id, to_string(target->kind)));
        }
    }
}

}  // namespace nclink::model_detail
