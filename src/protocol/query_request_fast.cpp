// The streaming Query request decoder (see the header for its contract).
// A SAX handler walks the fixed shape of 8.2.11,
//   {"@id": scalar, "guid": string, "ids": [ "id" | {"id": string, "params": any}, ... ], "privateInfo": any}
// and gives up (returns false, so the parse stops) at the first thing the
// tree decoder would refuse or would read differently. Only the values the
// request carries as free JSON (params, privateInfo) are built as Json, by
// the same rules as nlohmann's tree parser (a repeated key: the last wins).
#include "protocol/query_request_fast.hpp"
#include "protocol/dtu_codec.hpp"
#include "protocol/plain_scanner.hpp"

#include <vector>

namespace nclink::protocol_detail {
namespace {

// Builds one free JSON value from SAX events, as the tree parser would.
class ValueBuilder {
public:
    bool active() const noexcept { return active_; }
    void begin() {
        active_ = true;
        value_ = Json();
        stack_.clear();
        slot_ = nullptr;
    }
    // Returns true when the value is complete.
    bool scalar(Json v) {
        place(std::move(v));
        return stack_.empty();
    }
    void open(Json container) { stack_.push_back(place(std::move(container))); }
    void key(const std::string& k) { slot_ = &(*stack_.back())[k]; }
    bool close() {
        stack_.pop_back();
        return stack_.empty();
    }
    Json take() {
        active_ = false;
        return std::move(value_);
    }

private:
    Json* place(Json v) {
        if (stack_.empty()) {
            value_ = std::move(v);
            return &value_;
        }
        Json& top = *stack_.back();
        if (top.is_array()) {
            top.push_back(std::move(v));
            return &top.back();
        }
        *slot_ = std::move(v);
        return slot_;
    }

    bool active_ = false;
    Json value_;
    std::vector<Json*> stack_;  // open containers; a parent is never appended to while a child is open
    Json* slot_ = nullptr;      // the member the next value of the innermost object goes to
};

class QueryRequestSax {
public:
    /// An entry takes at least 11 bytes ({"id":"x"},): room for as many as
    /// `payload_size` can hold, so a large Query's list is not regrown ~10 times.
    explicit QueryRequestSax(std::size_t payload_size) { request_.ids.reserve(payload_size / 11); }

    using number_integer_t = Json::number_integer_t;
    using number_unsigned_t = Json::number_unsigned_t;
    using number_float_t = Json::number_float_t;
    using string_t = Json::string_t;
    using binary_t = Json::binary_t;

    bool null() { return scalar(Json(nullptr)); }
    bool boolean(bool v) { return scalar(Json(v)); }
    bool number_integer(number_integer_t v) { return scalar(Json(v)); }
    bool number_unsigned(number_unsigned_t v) { return scalar(Json(v)); }
    bool number_float(number_float_t v, const string_t&) { return scalar(Json(v)); }
    bool string(string_t& v) {
        if (builder_.active()) return finish_free(builder_.scalar(Json(v)));
        if (skipping_) return true;
        if (where_ == Where::top) {
            if (key_ == Key::guid) {
                request_.guid = std::move(v);
                return true;
            }
            return scalar_at_top(Json(v));
        }
        if (where_ == Where::ids) {  // liberal: ["010203"] for [{"id":"010203"}]
            request_.ids.push_back(QueryItem{std::move(v), std::nullopt});
            return true;
        }
        if (where_ == Where::entry && key_ == Key::id) {
            item_.id = std::move(v);
            return true;
        }
        return scalar(Json(v));
    }
    bool binary(binary_t&) { return false; }  // never from JSON text

    bool start_object(std::size_t) {
        if (builder_.active()) {
            builder_.open(Json::object());
            return true;
        }
        if (skipping_) return ++skipping_, true;
        switch (where_) {
            case Where::outside: where_ = Where::top; return true;
            case Where::ids:
                where_ = Where::entry;
                item_ = QueryItem{};
                seen_id_ = seen_params_ = false;
                return true;
            default: return open_free(Json::object());
        }
    }
    bool start_array(std::size_t) {
        if (builder_.active()) {
            builder_.open(Json::array());
            return true;
        }
        if (skipping_) return ++skipping_, true;
        if (where_ == Where::top && key_ == Key::ids) {
            where_ = Where::ids;
            return true;
        }
        if (where_ == Where::outside || where_ == Where::ids) return false;  // not an object / an entry that is no object
        return open_free(Json::array());
    }
    bool key(string_t& k) {
        if (builder_.active()) {
            builder_.key(k);
            return true;
        }
        if (skipping_) return true;
        if (where_ == Where::top) {
            key_ = k == "@id"           ? Key::at_id
                   : k == "guid"        ? Key::guid
                   : k == "ids"         ? Key::ids
                   : k == "privateInfo" ? Key::private_info
                                        : Key::other;
            return once(key_ == Key::at_id, seen_at_id_) && once(key_ == Key::guid, seen_guid_) &&
                   once(key_ == Key::ids, seen_ids_) && once(key_ == Key::private_info, seen_private_info_);
        }
        key_ = k == "id" ? Key::id : k == "params" ? Key::params : Key::other;
        return once(key_ == Key::id, seen_id_) && once(key_ == Key::params, seen_params_);
    }
    bool end_object() {
        if (builder_.active()) return finish_free(builder_.close());
        if (skipping_) return --skipping_, true;
        if (where_ == Where::entry) {
            if (!seen_id_) return false;  // 102/413 from the tree decoder
            request_.ids.push_back(std::move(item_));
            where_ = Where::ids;
            return true;
        }
        where_ = Where::done;
        return seen_ids_;  // "ids" is required
    }
    bool end_array() {
        if (builder_.active()) return finish_free(builder_.close());
        if (skipping_) return --skipping_, true;
        where_ = Where::top;
        key_ = Key::other;
        return true;
    }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) { return false; }

    bool complete() const noexcept { return where_ == Where::done; }
    QueryRequest take() { return std::move(request_); }

private:
    enum class Where { outside, top, ids, entry, done };
    enum class Key { other, at_id, guid, ids, private_info, id, params };

    // A key the decoder reads may come once: with two, the tree keeps the
    // last and so would this, but refusing here keeps the proof simple.
    static bool once(bool is_it, bool& seen) {
        if (!is_it) return true;
        if (seen) return false;
        seen = true;
        return true;
    }

    bool scalar(Json v) {
        if (builder_.active()) return finish_free(builder_.scalar(std::move(v)));
        if (skipping_) return true;
        if (where_ == Where::top) return scalar_at_top(std::move(v));
        if (where_ == Where::entry) {
            if (key_ == Key::params) {
                item_.params = std::move(v);
                return true;
            }
            return key_ == Key::other;  // a non-string "id": 402 from the tree decoder
        }
        return false;  // outside an object, or an ids entry that is neither string nor object
    }

    bool scalar_at_top(Json v) {
        switch (key_) {
            case Key::at_id:
                request_.msg_id = std::move(v);  // any scalar is echoed verbatim
                return true;
            case Key::private_info: request_.private_info = std::move(v); return true;
            case Key::other: return true;
            default: return false;  // a guid that is no string, ids that are no array
        }
    }

    // A structure where the request allows free JSON (params, privateInfo),
    // or one under a key the decoder does not read (skipped).
    bool open_free(Json container) {
        const bool free = (where_ == Where::top && key_ == Key::private_info) || (where_ == Where::entry && key_ == Key::params);
        if (free) {
            builder_.begin();
            builder_.open(std::move(container));
            return true;
        }
        if (key_ != Key::other) return false;  // a structured @id, guid or id
        skipping_ = 1;
        return true;
    }

    bool finish_free(bool complete) {
        if (!complete) return true;
        if (where_ == Where::top) request_.private_info = builder_.take();
        else item_.params = builder_.take();
        return true;
    }

    QueryRequest request_;
    QueryItem item_;
    Where where_ = Where::outside;
    Key key_ = Key::other;
    bool seen_at_id_ = false, seen_guid_ = false, seen_ids_ = false, seen_private_info_ = false;
    bool seen_id_ = false, seen_params_ = false;
    int skipping_ = 0;  // depth inside a skipped structure
    ValueBuilder builder_;
};

// The plain form nearly every application sends, read by a direct scan:
//   {"@id":"...","guid":"...","ids":[{"id":"..."},...]}
// keys in any order, JSON whitespace anywhere between tokens, entries as
// objects with "id" only or as bare strings, "@id" and "guid" optional,
// every string printable ASCII without escapes. No lexer, no token buffers,
// no SAX calls: a 100-item Query in a few microseconds where the SAX pass
// takes ~15. Anything else (a number @id, params, privateInfo, another key,
// an escape, a byte outside 0x20-0x7E, a key twice) is left to the SAX pass.

// One entry of "ids": {"id":"..."} or "...".
bool plain_entry(PlainScanner& scan, QueryRequest& out) {
    std::string_view id;
    if (scan.take('{')) {
        std::string_view key;
        if (!scan.string(key) || key != "id" || !scan.take(':') || !scan.string(id) || !scan.take('}')) return false;
    } else if (!scan.string(id)) {
        return false;
    }
    out.ids.push_back(QueryItem{std::string(id), std::nullopt});
    return true;
}

}  // namespace

std::optional<QueryRequest> plain_decode_query_request(std::string_view payload) {
    QueryRequest out;
    const bool plain = plain_request(payload, "ids", out.msg_id, out.guid, [&](PlainScanner& scan) {
        out.ids.reserve(payload.size() / 11);  // as QueryRequestSax
        return plain_list(scan, [&](PlainScanner& entry) { return plain_entry(entry, out); });
    });
    if (!plain) return std::nullopt;
    return out;
}

std::optional<QueryRequest> fast_decode_query_request(std::string_view payload) {
    if (auto plain = plain_decode_query_request(payload)) return plain;
    if (!depth_ok(payload)) return std::nullopt;
    QueryRequestSax sax(payload.size());
    try {
        if (!Json::sax_parse(payload.begin(), payload.end(), &sax) || !sax.complete()) return std::nullopt;
    } catch (...) {
        return std::nullopt;  // the tree decoder reports it
    }
    return sax.take();
}

}  // namespace nclink::protocol_detail
