#include "conform/report.hpp"

#include <fmt/format.h>

namespace nclink::conform {
namespace {

std::string verdict_text(Verdict v) { return v == Verdict::pass ? "pass" : "fail"; }

// Table cells: no line breaks, no pipes.
std::string cell(std::string text) {
    for (auto& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    std::string out;
    for (char c : text) {
        if (c == '|') out += "\\|";
        else out += c;
    }
    return out;
}

std::string supported_text(const ItemResult& i) {
    switch (i.outcome) {
        case Outcome::pass:
        case Outcome::fail: return "yes";
        case Outcome::not_supported: return "no";
        case Outcome::skipped: return "-";
    }
    return "-";
}

std::string result_text(const ItemResult& i) {
    switch (i.outcome) {
        case Outcome::pass: return "**pass**";
        case Outcome::fail: return "**FAIL**";
        case Outcome::not_supported: return "not supported";
        case Outcome::skipped: return "skipped";
    }
    return "";
}

void item_rows(std::string& md, const TestRecord& r, std::initializer_list<const char*> keys) {
    md += "| Item | C.1 row | Standard | C.1 | Supported | Result | Remarks |\n|---|---|---|---|---|---|---|\n";
    for (const char* key : keys) {
        const ItemResult* i = r.find(key);
        if (!i) continue;
        md += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", cell(i->title), cell(i->c1_row), cell(i->clause),
                          i->c1_mandatory ? "mandatory" : "optional", supported_text(*i), result_text(*i), cell(i->summary));
    }
    md += "\n";
}

}  // namespace

std::string render_markdown(const TestRecord& r) {
    std::string md;
    md += "# NC-Link conformance test record (GB/T 41970-2022, table C.1)\n\n";
    md += "## Basic information\n\n| | |\n|---|---|\n";
    md += fmt::format("| Test object | adapter `{}` (type 1-3 of 9.1.3: tested over the broker) |\n", cell(r.device));
    md += fmt::format("| Test object version | model version {} |\n", r.model_version.empty() ? "unknown" : cell(r.model_version));
    md += fmt::format("| Test system | {} {} |\n", r.tool, r.tool_version);
    md += fmt::format("| Broker | {} |\n", cell(r.broker));
    md += fmt::format("| Tester terminal id (ex_cid) | `{}` |\n", cell(r.client_id));
    md += fmt::format("| Test date | {} |\n", r.date);
    md += fmt::format("| Writes allowed | {} |\n\n",
                      r.allow_write ? "yes (--allow-write): every change was undone" : "no (read-only run)");

    md += fmt::format("## Verdict: **{}**\n\n", r.verdict() == Verdict::pass ? "PASS" : "FAIL");
    md += fmt::format("{} passed, {} failed, {} not supported, {} skipped.", r.count(Outcome::pass), r.count(Outcome::fail),
                      r.count(Outcome::not_supported), r.count(Outcome::skipped));
    md +=
        " Not supported and skipped items are not passes; only a failed item, or a required item (Probe/Query, the model "
        "file, Query) that is not supported, fails the verdict.\n\n";

    md += "## Connection test (table 55)\n\n";
    item_rows(md, r, {"register", "discovery"});

    md += "## Model file data item check (9.3.2)\n\n";
    if (r.objects) {
        const auto& o = *r.objects;
        md += "| Objects | Standard type | Custom type |\n|---|---|---|\n";
        md += fmt::format("| Component objects | {} | {} |\n", o.components_standard, o.components_custom);
        md += fmt::format("| Data objects | {} | {} |\n", o.data_standard, o.data_custom);
        md += fmt::format("| Sample channels (adapter provides) | {} | |\n", o.channels);
        md += fmt::format("| Methods (adapter provides) | {} | |\n\n", o.methods);
    } else {
        md += "No model could be read.\n\n";
    }

    md += "## Data transmission interface tests (tables 56-62)\n\n";
    item_rows(md, r,
              {"probe", "model-file", "model-set", "query", "state", "set", "sampling", "method-call", "method-status",
               "method-control", "method-result", "event-register", "event-data", "event-unregister", "dynamic-register",
               "dynamic-sample", "dynamic-unregister"});

    md += "## Test process record\n\n";
    bool any = false;
    for (const auto& i : r.items) {
        if (i.evidence.empty() && i.notes.empty()) continue;
        any = true;
        md += fmt::format("### {} - {}\n\n", i.title, to_string(i.outcome));
        for (const auto& e : i.evidence) {
            md += fmt::format("- {}\n", e.note);
            if (!e.topic.empty()) md += fmt::format("  - topic: `{}`\n", e.topic);
            if (!e.dtu.empty()) md += fmt::format("\n  ```json\n  {}\n  ```\n\n", e.dtu);
        }
        for (const auto& n : i.notes) md += fmt::format("- note: {}\n", n);
        md += "\n";
    }
    if (!any) md += "Nothing to report: no failure, no remark.\n\n";
    md += fmt::format("## Test conclusion\n\n{} ({}).\n", r.verdict() == Verdict::pass ? "PASS" : "FAIL",
                      r.verdict() == Verdict::pass ? "no item failed" : "see the items marked FAIL above");
    return md;
}

Json render_json(const TestRecord& r) {
    Json items = Json::array();
    for (const auto& i : r.items) {
        Json evidence = Json::array();
        for (const auto& e : i.evidence) evidence.push_back(Json{{"note", e.note}, {"topic", e.topic}, {"dtu", e.dtu}});
        Json supported = i.outcome == Outcome::skipped ? Json() : Json(i.outcome != Outcome::not_supported);
        items.push_back(Json{{"key", i.key},
                             {"title", i.title},
                             {"c1_row", i.c1_row},
                             {"clause", i.clause},
                             {"c1_mandatory", i.c1_mandatory},
                             {"required", i.required},
                             {"supported", supported},
                             {"outcome", std::string(to_string(i.outcome))},
                             {"summary", i.summary},
                             {"notes", i.notes},
                             {"evidence", evidence}});
    }
    Json objects;
    if (r.objects) {
        const auto& o = *r.objects;
        objects = Json{{"components", Json{{"standard", o.components_standard}, {"custom", o.components_custom}}},
                       {"data_objects", Json{{"standard", o.data_standard}, {"custom", o.data_custom}}},
                       {"sample_channels", o.channels},
                       {"methods", o.methods}};
    }
    return Json{{"standard", "GB/T 41970-2022"},
                {"record", "table C.1"},
                {"tool", Json{{"name", r.tool}, {"version", r.tool_version}}},
                {"basic", Json{{"device", r.device},
                               {"model_version", r.model_version},
                               {"broker", r.broker},
                               {"client_id", r.client_id},
                               {"date", r.date},
                               {"allow_write", r.allow_write}}},
                {"verdict", verdict_text(r.verdict())},
                {"counts", Json{{"pass", r.count(Outcome::pass)},
                                {"fail", r.count(Outcome::fail)},
                                {"not_supported", r.count(Outcome::not_supported)},
                                {"skipped", r.count(Outcome::skipped)}}},
                {"objects", objects},
                {"items", items}};
}

}  // namespace nclink::conform
