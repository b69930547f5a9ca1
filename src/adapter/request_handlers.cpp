#include "adapter/request_handlers.hpp"
#include "protocol/driver_failure.hpp"

namespace nclink::detail {
namespace {

Error unknown_item(const std::string& id) {
    return make_error(ErrorCode::node_not_exists, fmt::format("no data item '{}' on this device", id));
}

Error not_served(const std::string& id) { return make_error(ErrorCode::unavailable, "the driver does not serve " + id); }

// A failure of the driver's call (its own, or the SDK's about that call:
// timeout, machine disconnected): status and vendor text (docs/wire.md).
template <class Item>
void put_driver_failure(Item& item, const Error& error) {
    auto failure = driver_failure(error);
    item.status = std::move(failure.status);
    item.private_info = std::move(failure.private_info);
}

}  // namespace

QueryResponse handle_query(const QueryRequest& request, const HandlerContext& context) {
    auto response = make_reply<QueryResponse>(request, context.dev);
    response.values.resize(request.ids.size());

    struct DriverItem {
        std::size_t slot;
        QueryParams params;
        DataKind kind;
    };
    std::vector<PointRef> points;
    std::vector<DriverItem> driver_items;

    for (std::size_t i = 0; i < request.ids.size(); ++i) {
        const QueryItem& item = request.ids[i];
        QueryResult& result = response.values[i];
        result.id = item.id;
        result.params = item.params;
        const DataObject* object = context.state.item(item.id);
        if (!object && context.stats && !context.stats_item.empty() && item.id == context.stats_item) {
            // The SDK's own statistics (docs/sampling.md): a dict, so `keys` selects parts.
            auto values = evaluate_query(item.params.value_or(Json(nullptr)), context.stats(), DataKind::dict);
            if (values)
                result.values = std::move(values).value();
            else
                result.status = ResponseStatus(values.error());
            continue;
        }
        if (!object) {
            result.status = ResponseStatus(unknown_item(item.id));
            continue;
        }
        auto parsed = parse_query(item.params.value_or(Json(nullptr)), object->kind);
        if (!parsed) {
            result.status = ResponseStatus(parsed.error());
            continue;
        }
        if (context.state.sdk_held(item.id)) {
            auto values = context.state.store->query(item.id, item.params.value_or(Json(nullptr)));
            if (values)
                result.values = std::move(values).value();
            else
                result.status = ResponseStatus(values.error());
            continue;
        }
        PointRef point = context.state.point(item.id, object->kind);
        if (point.handle == nclink::not_served) {
            put_driver_failure(result, not_served(item.id));
            continue;
        }
        points.push_back(std::move(point));
        driver_items.push_back(DriverItem{i, std::move(parsed).value(), object->kind});
    }

    if (!points.empty()) {
        auto read = context.driver_expired
                        ? std::vector<Result<Json>>(points.size(), Result<Json>(*context.driver_expired))
                        : context.driver.read(points, context.state.generation());
        for (std::size_t k = 0; k < driver_items.size(); ++k) {
            QueryResult& result = response.values[driver_items[k].slot];
            if (!read[k].ok()) {
                context.logger.debug("query {}: {}", result.id, read[k].error().describe());
                put_driver_failure(result, read[k].error());
                continue;
            }
            auto values = evaluate(driver_items[k].params, read[k].value(), driver_items[k].kind);
            if (values)
                result.values = std::move(values).value();
            else
                result.status = ResponseStatus(values.error());
        }
    }
    return response;
}

SetResponse handle_set(const SetRequest& request, const HandlerContext& context) {
    auto response = make_reply<SetResponse>(request, context.dev);
    response.results.resize(request.values.size());

    struct DriverItem {
        std::size_t slot;
        SetParams params;
        const DataObject* object;
    };
    std::vector<DriverItem> driver_items;
    std::vector<PointRef> points;
    bool store_changed = false;

    for (std::size_t i = 0; i < request.values.size(); ++i) {
        const SetItem& item = request.values[i];
        SetResult& result = response.results[i];
        result.id = item.id;
        const DataObject* object = context.state.item(item.id);
        const Json params = item.params.value_or(Json(nullptr));
        if (!object) {
            result.status = ResponseStatus(unknown_item(item.id));
            result.params = item.params;
            continue;
        }
        if (!object->setable) {
            result.status = ResponseStatus(make_error(ErrorCode::permission_denied, item.id + " is not setable"));
            result.params = item.params;
            continue;
        }
        if (context.state.sdk_held(item.id)) {
            auto done = context.state.store->set(item.id, params);
            if (done)
                store_changed = true;
            else {
                result.status = ResponseStatus(done.error());
                result.params = item.params;
            }
            continue;
        }
        auto parsed = parse_set(params, object->kind);
        if (!parsed) {
            result.status = ResponseStatus(parsed.error());
            result.params = item.params;
            continue;
        }
        PointRef point = context.state.point(item.id, object->kind);
        if (point.handle == nclink::not_served) {
            put_driver_failure(result, not_served(item.id));
            result.params = item.params;
            continue;
        }
        points.push_back(std::move(point));
        driver_items.push_back(DriverItem{i, std::move(parsed).value(), object});
    }

    if (!driver_items.empty()) {
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
            write.params = item.params.value_or(Json(nullptr));
            if (current[k].ok()) {
                Json next = current[k].value();
                if (auto applied = apply(d.params, next, d.object->kind, true); !applied) {
                    result.status = ResponseStatus(applied.error());
                    result.params = item.params;
                    continue;
                }
                write.new_value = std::move(next);
            }
            auto written = context.driver.write(write, generation);
            if (!written) {
                context.logger.debug("set {}: {}", item.id, written.error().describe());
                put_driver_failure(result, written.error());
                result.params = item.params;
            }
        }
    }

    if (store_changed) {
        if (auto persisted = context.host.persist_values(*context.state.store); !persisted)
            context.logger.warn("could not persist settable values: {}", persisted.error().describe());
    }
    return response;
}

ProbeQueryResponse handle_probe_query(const ProbeQueryRequest& request, const HandlerContext& context) {
    auto response = make_reply<ProbeQueryResponse>(request, context.dev);
    response.probe = *context.state.probe_json;
    return response;
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

}  // namespace nclink::detail
