// The fidelity parts of the query and model-set items: values against
// chapter 7, the Query forms of appendix A, and the table-19 reason of a
// refused Probe/Set (checks_fidelity.hpp has the checks themselves).
#include "conform/checks_fidelity.hpp"
#include "conform/runner_impl.hpp"

#include <fmt/format.h>

namespace nclink::conform::detail {

void Runner::query_fidelity(ItemResult& q) {
    // Every value answered must fit what the model declares (chapter 7).
    const ValueRules rules(*model);
    std::size_t broken = 0;
    for (const auto& [id, value] : whole_values) {
        for (const auto& p : check_value_rule(rules, id, value)) {
            if (++broken <= 8) q.fail(fmt::format("{}: {}", id, p), whole_values_topic, value.dump());
        }
    }
    if (broken > 8) q.fail(fmt::format("{} more values break chapter 7", broken - 8));

    // Appendix A Query_Params forms on a list and a dict item whose value
    // has an element: get_attribute (appendix A's spelling), and
    // offset/length on a list element. An adapter may answer them NG for
    // the data (101, 405...), not as malformed (412/413).
    const DataObject* list = nullptr;
    const DataObject* dict = nullptr;
    for (const auto& [id, value] : whole_values) {
        const DataObject* obj = model->data_object(id);
        if (!obj) continue;
        if (!list && obj->kind == DataKind::list && value.is_array() && !value.empty()) list = obj;
        if (!dict && obj->kind == DataKind::dict && value.is_object() && !value.empty()) dict = obj;
    }
    // A list whose whole value came back broken is still asked by index: the
    // form must be understood whatever the data (an NG for the data is fine).
    if (!list)
        for (const auto& obj : model->data_objects())
            if (obj.kind == DataKind::list && !obj.value) {
                list = &obj;
                break;
            }
    Json entries = Json::array();
    std::vector<std::string> ids, forms;
    if (list) {
        entries.push_back(Json{{"id", list->id}, {"params", {{"operation", "get_attribute"}, {"indexes", Json::array({"0"})}}}});
        forms.push_back("get_attribute with indexes (appendix A Query_Params)");
        entries.push_back(
            Json{{"id", list->id},
                 {"params", {{"operation", "get_value"}, {"indexes", Json::array({"0"})}, {"offset", 0}, {"length", 1}}}});
        forms.push_back("get_value with indexes, offset and length (appendix A Query_Params)");
        ids.insert(ids.end(), 2, list->id);
    }
    if (dict) {
        const std::string key = whole_values[dict->id].begin().key();
        entries.push_back(Json{{"id", dict->id}, {"params", {{"operation", "get_attribute"}, {"keys", Json::array({key})}}}});
        forms.push_back("get_attribute with keys (appendix A Query_Params)");
        ids.push_back(dict->id);
    }
    if (entries.empty()) {
        q.notes.push_back("no list or dict item with an element: the appendix A Query forms were not tried");
        return;
    }
    auto x = request_kind(TopicKind::query_request, Json{{"guid", dev}, {"ids", entries}});
    if (!x.dtu) {
        q.fail("no answer to the Query of the appendix A forms");
        return;
    }
    if (auto problems = check_query_response(*x.dtu, x.sent_id, dev, ids); !problems.empty()) fail_with(q, join(problems), x);
    for (std::size_t k = 0; k < forms.size(); ++k) {
        const Json* entry = result_entry(*x.dtu, k);
        if (!entry) continue;
        for (const auto& p : check_form_understood(*entry, forms[k]))
            q.fail(fmt::format("{}: {}", ids[k], p), x.reply->message.topic, entry->dump());
    }
}

void Runner::refused_model_set(ItemResult& m) {
    // An object with none of what table 1 requires is no model: the
    // adapter refuses it (8.2.9.3), with a table-19 reason (table 20).
    auto x = request_kind(TopicKind::probe_set_request, Json{{"guid", dev}, {"probe", Json::object()}});
    if (!x.dtu) return;  // silence is judged by the Probe/Set that follows
    if (is_ok(*x.dtu)) {
        fail_with(
            m, "Probe/Set of an empty object (no id, no devices) was accepted: the adapter does not check the model (8.2.9.3)", x);
        (void)request_kind(TopicKind::probe_set_request, Json{{"guid", dev}, {"probe", raw_model}});  // put the model back
        return;
    }
    if (auto problems = check_status_keys(*x.dtu); !problems.empty()) fail_with(m, "refused Probe/Set: " + join(problems), x);
}

}  // namespace nclink::conform::detail
