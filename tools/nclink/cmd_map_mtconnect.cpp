// `nclink map --from-mtconnect PROBE [--device D] [-o FILE]`: the NC-Link
// model of an MTConnect device, read from its Devices document (a file, or
// an agent's http://host:port whose /probe is read), GB/T 39561.3 appendix A
// read in reverse (docs/mapping.md "The reverse direction"). The model goes
// to stdout or FILE; every DataItem or component with no NC-Link counterpart
// and every note goes to stderr. Exit 0 written, 1 unreadable or unusable
// probe, 2 usage error. Needs the MTConnect source driver (drivers/mtconnect).
#include "commands.hpp"

#if NCLINK_WITH_MTCONNECT_SOURCE
#include "mtconnect/agent_source.hpp"
#include "mtconnect/probe_document.hpp"
#include "mtconnect/reverse_mapping.hpp"
#endif

#include <nclink/model.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace nclink::cli {

int run_map_from_mtconnect(const std::string& probe, const std::string& device, const std::string& output) {
#if NCLINK_WITH_MTCONNECT_SOURCE
    std::string text;
    if (probe.rfind("http://", 0) == 0) {
        auto url = mtconnect::parse_agent_url(probe);
        if (!url.ok()) {
            std::fprintf(stderr, "nclink map: %s\n", url.error().message.c_str());
            return 1;
        }
        auto body = mtconnect::agent_get(url.value(), "/probe", std::chrono::seconds(10));
        if (!body.ok()) {
            std::fprintf(stderr, "nclink map: %s\n", body.error().message.c_str());
            return 1;
        }
        text = std::move(body).value();
    } else {
        std::ifstream in(probe, std::ios::binary);
        if (!in) {
            std::fprintf(stderr, "nclink map: cannot read %s\n", probe.c_str());
            return 1;
        }
        std::ostringstream all;
        all << in.rdbuf();
        text = all.str();
    }
    auto doc = mtconnect::read_probe(text);
    if (!doc.ok()) {
        std::fprintf(stderr, "nclink map: %s: %s\n", probe.c_str(), doc.error().message.c_str());
        return 1;
    }
    mtconnect::ReverseOptions options;
    options.device = device;
    auto reversed = mtconnect::reverse_map(doc.value(), options);
    if (!reversed.ok()) {
        std::fprintf(stderr, "nclink map: %s: %s\n", probe.c_str(), reversed.error().message.c_str());
        return 1;
    }
    // The generated model is checked like any other before it is written.
    const std::string json = reversed->model.dump(2) + "\n";
    const LoadResult loaded = parse_model(json);
    for (const auto& p : loaded.problems)
        if (p.severity == Severity::fatal)
            std::fprintf(stderr, "nclink map: the generated model is refused: %s: %s\n",
                         p.pointer.empty() ? "/" : p.pointer.c_str(), p.message.c_str());
    if (!loaded.ok()) return 1;
    for (const auto& u : reversed->unmatched)
        std::fprintf(stderr, "no counterpart: %s (%s) -> %s\n", u.mt_id.c_str(), u.mtconnect.c_str(), u.became.c_str());
    for (const auto& n : reversed->notes) std::fprintf(stderr, "note: %s\n", n.c_str());
    if (output.empty()) {
        std::fwrite(json.data(), 1, json.size(), stdout);
        return std::fflush(stdout) == 0 ? 0 : 1;
    }
    std::ofstream out(output, std::ios::binary | std::ios::trunc);
    out << json;
    out.close();
    if (!out) {
        std::fprintf(stderr, "nclink map: cannot write %s\n", output.c_str());
        return 1;
    }
    std::fprintf(stderr, "nclink map: wrote %s (%zu item(s) without counterpart)\n", output.c_str(), reversed->unmatched.size());
    return 0;
#else
    (void)probe;
    (void)device;
    (void)output;
    std::fprintf(stderr, "nclink map: --from-mtconnect needs the MTConnect source driver, not in this build\n");
    return 1;
#endif
}

}  // namespace nclink::cli
