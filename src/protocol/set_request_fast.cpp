// The plain-form Set request scan (see the header for its contract).
#include "protocol/set_request_fast.hpp"
#include "protocol/plain_scanner.hpp"

namespace nclink::protocol_detail {
namespace {

// "params": an object of plain scalars, each key once ({"value":42},
// {"index":2,"value":"on"}). A structure inside is left to the tree.
bool plain_params(PlainScanner& scan, Json& out) {
    if (!scan.take('{')) return false;
    out = Json::object();
    if (scan.take('}')) return true;
    do {
        std::string_view key;
        Json value;
        if (!scan.string(key) || !scan.take(':') || !scan.scalar(value)) return false;
        auto [slot, fresh] = out.emplace(std::string(key), std::move(value));
        if (!fresh) return false;  // the tree keeps the last; not plain
    } while (scan.take(','));
    return scan.take('}');
}

// One entry of "values": {"id":"...","params":{...}}, keys in any order,
// "params" optional (a missing one is answered per item, 102).
bool plain_entry(PlainScanner& scan, SetRequest& out) {
    if (!scan.take('{')) return false;
    SetItem item;
    bool seen_id = false, seen_params = false;
    if (!scan.next_is('}')) {
        do {
            std::string_view key, text;
            if (!scan.string(key) || !scan.take(':')) return false;
            if (key == "id" && !seen_id) {
                if (!scan.string(text)) return false;
                item.id = std::string(text);
                seen_id = true;
            } else if (key == "params" && !seen_params) {
                Json params;
                if (!plain_params(scan, params)) return false;
                item.params = std::move(params);
                seen_params = true;
            } else {
                return false;
            }
        } while (scan.take(','));
    }
    if (!scan.take('}') || !seen_id) return false;
    out.values.push_back(std::move(item));
    return true;
}

}  // namespace

std::optional<SetRequest> plain_decode_set_request(std::string_view payload) {
    SetRequest out;
    const bool plain = plain_request(payload, "values", out.msg_id, out.guid, [&](PlainScanner& scan) {
        return plain_list(scan, [&](PlainScanner& entry) { return plain_entry(entry, out); });
    });
    if (!plain) return std::nullopt;
    return out;
}

}  // namespace nclink::protocol_detail
