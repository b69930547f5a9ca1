// Internal: a Query response (8.2.12, table 33) written entry by entry.
//
// encode<QueryResponse> writes through it. The adapter's Query handler
// writes the driver's values straight in (add_value), without first making
// a QueryResult for each: for a 100-item Query that struct (a Json array per
// value, walked here, then freed) cost about a third of the handler's time
// (docs/performance.md "Requests").
#pragma once

#include "protocol/json_text_writer.hpp"

#include <nclink/dtu.hpp>

#include <cstddef>
#include <optional>
#include <string>

namespace nclink::protocol_detail {

class QueryAnswerText {
public:
    /// Opens the answer with `head`'s keys that sort before "values" ("@id",
    /// code/error/reason of a refusal, guid, privateInfo); its values are not
    /// written (add them). `entries` sizes the text (a hint).
    explicit QueryAnswerText(const QueryResponse& head, std::size_t entries = 0);
    QueryAnswerText(const QueryAnswerText&) = delete;
    QueryAnswerText& operator=(const QueryAnswerText&) = delete;

    /// One entry of "values", in request order.
    void add(const QueryResult& entry);
    /// The entry add() writes for a QueryResult with this id and params,
    /// status OK and values [value].
    void add_value(const std::string& id, const std::optional<Json>& params, const Json& value);
    /// The whole text; the writer is spent.
    std::string finish();

private:
    void open_entry();

    std::string text_;
    JsonTextWriter writer_{text_};
    bool first_entry_ = true;
};

}  // namespace nclink::protocol_detail
