// Progress of long work: the bar's text, and the plain lines off a terminal.
#include "progress.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <string>

using namespace nclink::cli;

namespace {

std::string read_all(std::FILE* f) {
    std::rewind(f);
    std::string out;
    char buffer[256];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) out.append(buffer, n);
    return out;
}

}  // namespace

TEST_CASE("progress bar: exactly the width, filled by the fraction") {
    const std::string half = render_bar("program_transfer", 0.5, "executing", 80);
    CHECK(half.size() == 80);
    CHECK_THAT(half, Catch::StartsWith("program_transfer [####################....................]  50.0% executing"));
    const std::string full = render_bar("x", 1.7, "", 60);
    CHECK(full.size() == 60);
    CHECK_THAT(full, Catch::Contains("100.0%"));
    const std::string cells = full.substr(full.find('[') + 1, full.find(']') - full.find('[') - 1);
    CHECK(cells == std::string(cells.size(), '#'));
    CHECK_THAT(render_bar("x", -1.0, "", 60), Catch::Contains("  0.0%"));
}

TEST_CASE("progress bar: narrow terminals shrink the bar then clip the texts") {
    const std::string narrow = render_bar("a-rather-long-method-name", 0.25, "executing step 3 of 12", 40);
    CHECK(narrow.size() == 40);
    CHECK_THAT(narrow, Catch::Contains("25.0%"));
    CHECK_THAT(narrow, Catch::Contains("[###"));
    const std::string tiny = render_bar("label", 0.5, "detail", 5);  // never below 20 columns
    CHECK(tiny.size() == 20);
}

TEST_CASE("progress bar: an unknown fraction draws a marker that moves") {
    const std::string a = render_bar("wait", std::nullopt, "", 60, 0);
    const std::string b = render_bar("wait", std::nullopt, "", 60, 5);
    CHECK(a != b);
    CHECK(std::count(a.begin(), a.end(), '#') == 1);
    CHECK(a.find('%') == std::string::npos);
}

TEST_CASE("progress lines: one line per change of detail or tenth, nothing when off") {
    std::FILE* out = std::tmpfile();
    REQUIRE(out != nullptr);
    {
        Progress p(ProgressMode::lines, out, "probe-set");
        for (int i = 0; i <= 100; ++i) p.update(i / 100.0, "mill-1");
        p.update(1.0, "mill-2");
        p.note("mill-1: OK");
    }
    const std::string text = read_all(out);
    std::fclose(out);
    CHECK(std::count(text.begin(), text.end(), '\n') == 13);  // 0%..100% by tenths, mill-2, the note
    CHECK_THAT(text, Catch::StartsWith("probe-set 0% mill-1\n"));
    CHECK_THAT(text, Catch::Contains("probe-set 100% mill-2\nmill-1: OK\n"));
    CHECK(text.find('\r') == std::string::npos);

    std::FILE* quiet = std::tmpfile();
    {
        Progress p(ProgressMode::off, quiet, "x");
        p.update(0.5, "y");
    }
    CHECK(read_all(quiet).empty());
    std::fclose(quiet);
    CHECK(progress_mode(true, false, stdout) == ProgressMode::off);
    CHECK(progress_mode(false, true, stdout) == ProgressMode::off);
}
