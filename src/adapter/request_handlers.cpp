#include "adapter/request_handlers.hpp"
#include "protocol/driver_failure.hpp"
#include "protocol/query_answer_text.hpp"

namespace nclink::adapter_detail {
namespace {

Error unknown_item(const std::string& id) {
    return make_error(ErrorCode::node_not_exists, fmt::format("no data item '{}' on this device", id));
}

// Appendix A (CMD_Set_Request) gives offset/length beside `params`, 8.2.13
// example 3 inside them: both are one request, folded into the params. The
// same key given in both places with different values is 409.
Result<Json> effective_params(const SetItem& item) {
    Json params = item.params.value_or(Json(nullptr));
    const std::pair<const char*, const std::optional<Json>*> beside[] = {{"offset", &item.offset}, {"length", &item.length}};
    for (const auto& [key, given] : beside) {
        if (!*given || (*given)->is_null()) continue;
        if (params.is_null()) params = Json::object();
        if (!params.is_object()) break;  // the values module answers a params that is no object
        const auto found = params.find(key);
        if (found != params.end() && !found->is_null() && *found != **given)
            return make_error(ErrorCode::arguments_nimiety, fmt::format("{} given beside params ({}) and inside them ({})", key,
                                                                        (*given)->dump(), found->dump()));
        params[key] = **given;
    }
    return params;
}

// What a Set result echoes: the params without the value(s) written;
// nothing when that leaves nothing (8.2.14 example 1: {"id","code":"OK"}).
std::optional<Json> echo_params(const Json& params) {
    if (params.is_null()) return std::nullopt;
    if (!params.is_object()) return params;
    Json out = params;
    out.erase("value");
    out.erase("values");
    if (out.empty()) return std::nullopt;
    return out;
}

// The driver's ref of an item found by ModelState::entry(), as
// ModelState::point() gives it: its binding's, or identified by id alone.
PointRef driver_ref(const feature_detail::ModelState::ItemEntry& found, const std::string& id) {
    return found.bound ? *found.bound : PointRef{id, found.object->kind, no_handle};
}

Error not_served(const std::string& id) { return make_error(ErrorCode::unavailable, "the driver does not serve " + id); }

// A failure of the driver's call (its own, or the SDK's about that call:
// timeout, machine disconnected): status and vendor text (docs/wire.md).
template <class Item>
void put_driver_failure(Item& item, const Error& error) {
    auto failure = protocol_detail::driver_failure(error);
    item.status = std::move(failure.status);
    item.private_info = std::move(failure.private_info);
}

}  // namespace

std::string handle_query(const QueryRequest& request, const HandlerContext& context) {
    // Each entry is settled in the first pass (an error, an SDK-held item),
    // or is the driver's: read in one batch, then written straight into the
    // answer when the item is asked for whole, the usual case.
    struct DriverItem {
        QueryParams params;
        DataKind kind;
        const ValueRule* rule;
    };
    struct Slot {
        bool driver;        // read from the driver, else settled
        std::size_t index;  // into driver_items (and points), or into settled
    };
    std::vector<Slot> slots;  // one per requested item, in order
    std::vector<QueryResult> settled;
    std::vector<PointRef> points;
    std::vector<DriverItem> driver_items;
    slots.reserve(request.ids.size());
    points.reserve(request.ids.size());
    driver_items.reserve(request.ids.size());
    static const Json no_params;

    const auto settle = [&](const QueryItem& item) -> QueryResult& {
        slots.push_back(Slot{false, settled.size()});
        QueryResult& result = settled.emplace_back();
        result.id = item.id;
        result.params = item.params;
        return result;
    };
    for (const QueryItem& item : request.ids) {
        const Json& params = item.params ? *item.params : no_params;
        const feature_detail::ModelState::ItemEntry found = context.state.entry(item.id);
        const DataObject* object = found.object;
        if (!object && context.stats && !context.stats_item.empty() && item.id == context.stats_item) {
            // The SDK's own statistics (docs/sampling.md): a dict, so `keys` selects parts.
            QueryResult& result = settle(item);
            auto values = evaluate_query(params, context.stats(), DataKind::dict);
            if (values) result.values = std::move(values).value();
            else result.status = ResponseStatus(values.error());
            continue;
        }
        if (!object) {
            settle(item).status = ResponseStatus(unknown_item(item.id));
            continue;
        }
        auto parsed = parse_query(params, object->kind);
        if (!parsed) {
            settle(item).status = ResponseStatus(parsed.error());
            continue;
        }
        // The driver's items, the bulk of a large Query, are found in the
        // binding without a look at the store (and its lock).
        const PointRef* bound = found.bound;
        if (!bound && context.state.sdk_held(item.id)) {
            QueryResult& result = settle(item);
            auto values = context.state.store->query(item.id, params);
            if (values) result.values = std::move(values).value();
            else result.status = ResponseStatus(values.error());
            continue;
        }
        if (bound && bound->handle == nclink::not_served) {
            put_driver_failure(settle(item), not_served(item.id));
            continue;
        }
        slots.push_back(Slot{true, driver_items.size()});
        points.push_back(driver_ref(found, item.id));
        driver_items.push_back(DriverItem{std::move(parsed).value(), object->kind, found.rule});
    }

    std::vector<Result<Json>> read;
    if (!points.empty())
        read = context.driver_expired ? std::vector<Result<Json>>(points.size(), Result<Json>(*context.driver_expired))
                                      : context.driver.read(points, context.state.generation());

    protocol_detail::QueryAnswerText answer(make_reply<QueryResponse>(request, context.dev), request.ids.size());
    for (std::size_t i = 0; i < slots.size(); ++i) {
        if (!slots[i].driver) {
            answer.add(settled[slots[i].index]);
            continue;
        }
        const std::size_t k = slots[i].index;
        const QueryItem& item = request.ids[i];
        if (context.values) context.values->screen(driver_items[k].rule, read[k], "query");
        if (read[k].ok() && driver_items[k].params.whole_item()) {
            answer.add_value(item.id, item.params, read[k].value());
            continue;
        }
        QueryResult result;
        result.id = item.id;
        result.params = item.params;
        if (!read[k].ok()) {
            context.logger.debug("query {}: {}", result.id, read[k].error().describe());
            put_driver_failure(result, read[k].error());
        } else if (auto values = evaluate(driver_items[k].params, std::move(read[k]).value(), driver_items[k].kind)) {
            result.values = std::move(values).value();
        } else {
            result.status = ResponseStatus(values.error());
        }
        answer.add(result);
    }
    return answer.finish();
}

SetResponse handle_set(const SetRequest& request, const HandlerContext& context) {
    auto response = make_reply<SetResponse>(request, context.dev);
    response.results.resize(request.values.size());

    struct DriverItem {
        std::size_t slot;
        SetParams params;
        const DataObject* object;
        Json raw;  // the item's params, offset/length folded in
        const ValueRule* rule;
    };
    std::vector<DriverItem> driver_items;
    std::vector<PointRef> points;
    bool store_changed = false;

    for (std::size_t i = 0; i < request.values.size(); ++i) {
        const SetItem& item = request.values[i];
        SetResult& result = response.results[i];
        result.id = item.id;
        const feature_detail::ModelState::ItemEntry found = context.state.entry(item.id);
        const DataObject* object = found.object;
        auto folded = effective_params(item);
        if (!folded) {
            result.status = ResponseStatus(folded.error());
            continue;
        }
        const Json params = std::move(folded).value();
        // 8.2.14's examples echo what was done (operation, key, index,
        // offset, length), OK or NG, never the value written.
        result.params = echo_params(params);
        if (!object) {
            result.status = ResponseStatus(unknown_item(item.id));
            continue;
        }
        if (!object->setable) {
            result.status = ResponseStatus(make_error(ErrorCode::permission_denied, item.id + " is not setable"));
            continue;
        }
        if (!found.bound && context.state.sdk_held(item.id)) {
            auto done = context.state.store->set(item.id, params);
            if (done) store_changed = true;
            else result.status = ResponseStatus(done.error());
            continue;
        }
        auto parsed = parse_set(params, object->kind);
        if (!parsed) {
            result.status = ResponseStatus(parsed.error());
            continue;
        }
        if (found.bound && found.bound->handle == nclink::not_served) {
            put_driver_failure(result, not_served(item.id));
            continue;
        }
        points.push_back(driver_ref(found, item.id));
        driver_items.push_back(DriverItem{i, std::move(parsed).value(), object, params, found.rule});
    }

    if (!driver_items.empty() && context.driver_expired) {
        // The deadline answers for a worker that never started this Set:
        // nothing reaches the driver, its items say why.
        for (const DriverItem& d : driver_items) put_driver_failure(response.results[d.slot], *context.driver_expired);
    } else if (!driver_items.empty()) {
        // Read current values once, so the operation is checked against the
        // machine's value (out of range, unknown key...) before anything is
        // written, and drivers that write whole items get the new value.
        const std::uint64_t generation = context.state.generation();
        auto current = context.driver.read(points, generation);
        for (std::size_t k = 0; k < driver_items.size(); ++k) {
            const DriverItem& d = driver_items[k];
            SetResult& result = response.results[d.slot];
            const SetItem& item = request.values[d.slot];
            WriteRequest write;
            write.id = item.id;
            write.kind = d.object->kind;
            write.handle = points[k].handle;
            write.params = d.raw;
            if (current[k].ok()) {
                Json next = current[k].value();
                if (auto applied = apply(d.params, next, d.object->kind, true); !applied) {
                    result.status = ResponseStatus(applied.error());
                    continue;
                }
                // Chapter 7: what the item would hold after the Set must fit
                // its rule (a "spinning" SPINDLE_MODE is refused, not written).
                // Judged only when the machine's value fits it: a Set is not
                // refused for a fault of the driver's value.
                const ValueRule* rule = d.rule;
                if (rule != nullptr && rule->check(next) != ValueFault::none &&
                    rule->check(current[k].value()) == ValueFault::none) {
                    result.status = ResponseStatus(rule->verify(next).error());
                    continue;
                }
                write.new_value = std::move(next);
            }
            auto written = context.driver.write(write, generation);
            if (!written) {
                context.logger.debug("set {}: {}", item.id, written.error().describe());
                put_driver_failure(result, written.error());
            }
        }
    }

    if (store_changed) {
        if (auto persisted = context.host.persist_values(*context.state.store); !persisted)
            context.logger.warn("could not persist settable values: {}", persisted.error().describe());
    }
    return response;
}

std::string handle_probe_query(const ProbeQueryRequest& request, const HandlerContext& context) {
    const auto response = make_reply<ProbeQueryResponse>(request, context.dev);
    std::string payload = to_json(response).dump(-1, ' ', false, Json::error_handler_t::replace);
    // Keys are sorted and "probe" sorts after "@id", "code" and "guid": it
    // goes last, before the closing brace.
    payload.pop_back();
    payload += ",\"probe\":";
    payload += *context.state.probe_text;
    payload += '}';
    return payload;
}

std::string refusal_reasons(const LoadResult& loaded, bool strict) {
    std::string text;
    for (const auto& p : loaded.problems) {
        if (p.severity == Severity::warning || (p.severity == Severity::conformance && !strict)) continue;
        if (!text.empty()) text += "; ";
        text += fmt::format("{}: {}: {}", p.pointer.empty() ? "/" : p.pointer, to_string(p.severity), p.message);
    }
    if (text.empty() && !loaded.model) text = "the model cannot be used";
    return text;
}

}  // namespace nclink::adapter_detail
