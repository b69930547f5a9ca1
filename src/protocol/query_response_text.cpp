// The text of a Query response (8.2.12, table 33), written straight out.
// A Query of many items gets the largest answer on the request path: built
// as a tree of nlohmann objects (a std::map per entry) and then dumped, 100
// items cost ~80 us on the reference VM, three quarters of it building the
// tree, more than the broker's whole round trip. The text here is byte for
// byte what to_json(dtu).dump() gives (keys in the order nlohmann's std::map
// sorts them), except that a double always gets its shortest digits
// (JsonTextWriter::number), which the protocol tests check on generated
// answers.
#include "protocol/dtu_codec.hpp"
#include "protocol/query_answer_text.hpp"

namespace nclink {
namespace protocol_detail {

QueryAnswerText::QueryAnswerText(const QueryResponse& head, std::size_t entries) {
    text_.reserve(64 + entries * 48);
    writer_.response_head(head.msg_id, head.status, head.guid, head.private_info);
    writer_.raw("\"values\":[");
}

void QueryAnswerText::open_entry() {
    writer_.raw(first_entry_ ? "{" : ",{");
    first_entry_ = false;
}

void QueryAnswerText::add(const QueryResult& entry) {
    open_entry();
    writer_.result_fields(entry.status, entry.id, entry.params, entry.private_info);
    if (entry.values) {
        writer_.raw(",\"values\":");
        writer_.value(*entry.values);
    }
    writer_.raw("}");
}

void QueryAnswerText::add_value(const std::string& id, const std::optional<Json>& params, const Json& value) {
    open_entry();
    writer_.result_fields(ResponseStatus::success(), id, params, std::nullopt);
    writer_.raw(",\"values\":[");
    writer_.value(value);
    writer_.raw("]}");
}

std::string QueryAnswerText::finish() {
    writer_.raw("]}");
    return std::move(text_);
}

}  // namespace protocol_detail

template <>
std::string encode<QueryResponse>(const QueryResponse& dtu) {
    protocol_detail::QueryAnswerText text(dtu, dtu.values.size());
    for (const QueryResult& entry : dtu.values) text.add(entry);
    return text.finish();
}

}  // namespace nclink
