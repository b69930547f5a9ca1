// `nclink watch --device GUID [--channel ID] [--count N]`: subscribe to the
// device's Sample DTUs and print a rolling table, one row per DTU: channel,
// beginTime and, per point, the latest value in that DTU. --json prints each
// DTU as one JSON line. --full-screen (and `nclink top`) shows every point's
// latest value in a table refreshed in place (live_view.hpp, terminal.hpp).
#include "cli_device.hpp"
#include "cli_inbox.hpp"
#include "live_view.hpp"
#include "terminal.hpp"

#include <algorithm>
#include <cstdio>
#include <map>

namespace nclink::cli {

const char* const watch_usage =
    "usage: nclink watch --device GUID [--channel ID] [--count N] [--full-screen] [options]\n"
    "       nclink top --device GUID [--channel ID] [options]\n"
    "  Prints the device's samples (Sample/GUID/+) as a rolling table: channel,\n"
    "  beginTime, then one column per point with its latest value in the DTU.\n"
    "  Runs until Ctrl-C, or until N DTUs with --count. --json: one DTU per line.\n"
    "  --full-screen (or `nclink top`): one row per point with its latest value\n"
    "  and age, refreshed in place; q quits, up/down (j/k), PgUp/PgDn scroll.\n"
    "  Needs a terminal.\n" NCLINK_CLI_GLOBAL_OPTIONS;

namespace {

std::string latest_value(const Json& point) {
    if (!point.is_array()) return point.dump();
    for (auto it = point.rbegin(); it != point.rend(); ++it)
        if (!it->is_null()) return it->dump(-1, ' ', false, Json::error_handler_t::replace);
    return "-";
}

std::string fit(std::string text, std::size_t width) {
    if (text.size() > width) text = text.substr(0, width - 1) + "~";
    return text;
}

class Table {
public:
    explicit Table(std::map<std::string, std::vector<std::string>> points) : points_(std::move(points)) {}

    void print(const SampleDtu& dtu) {
        const auto names = column_names(dtu);
        if (dtu.id != last_channel_ || ++rows_since_header_ >= 20) {
            std::printf("%-12s %-24s", "channel", "beginTime");
            for (const auto& n : names) std::printf(" %*s", static_cast<int>(width(n)), fit(n, width(n)).c_str());
            std::printf("\n");
            last_channel_ = dtu.id;
            rows_since_header_ = 0;
        }
        std::printf("%-12s %-24s", fit(dtu.id, 12).c_str(), format_time_ms(dtu.begin_time).c_str());
        for (std::size_t i = 0; i < names.size(); ++i) {
            const std::string value = i < dtu.data.size() ? latest_value(dtu.data[i]) : "-";
            std::printf(" %*s", static_cast<int>(width(names[i])), fit(value, width(names[i])).c_str());
        }
        std::printf("\n");
        std::fflush(stdout);
    }

private:
    static std::size_t width(const std::string& name) { return std::max<std::size_t>(name.size(), 12); }

    std::vector<std::string> column_names(const SampleDtu& dtu) const {
        std::vector<std::string> names;
        if (const auto it = points_.find(dtu.id); it != points_.end()) names = it->second;
        for (std::size_t i = names.size(); i < dtu.data.size(); ++i) names.push_back("p" + std::to_string(i + 1));
        return names;
    }

    std::map<std::string, std::vector<std::string>> points_;
    std::string last_channel_;
    int rows_since_header_ = 0;
};

std::int64_t wall_ms() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// The full-screen loop: keys every 100 ms at most, samples as they come, a
// redraw when something changed (and every second, for the ages).
int run_full_screen(const CliOptions& options, Inbox<SampleDtu>& inbox, std::map<std::string, std::vector<std::string>> points) {
    LiveView view(options.device, options.broker, std::move(points));
    FullScreen screen;
    auto last_draw = std::chrono::steady_clock::time_point{};
    bool dirty = true;
    while (!interrupted()) {
        switch (screen.read_key(std::chrono::milliseconds(100))) {
            case Key::quit: return 0;
            case Key::up: view.scroll(-1), dirty = true; break;
            case Key::down: view.scroll(1), dirty = true; break;
            case Key::page_up: view.scroll(-(screen.size().second - 3)), dirty = true; break;
            case Key::page_down: view.scroll(screen.size().second - 3), dirty = true; break;
            case Key::home: view.scroll_home(), dirty = true; break;
            default: break;
        }
        while (auto dtu = inbox.pop(std::chrono::steady_clock::now())) {
            view.apply(*dtu, wall_ms());
            dirty = true;
        }
        if (screen.resized()) dirty = true;
        const auto now = std::chrono::steady_clock::now();
        if (dirty || now - last_draw >= std::chrono::seconds(1)) {
            const auto [columns, rows] = screen.size();
            // One column spare: a character in the last column makes some
            // terminals wrap (and scroll) on the next one.
            screen.draw(view.render(columns - 1, rows, wall_ms()));
            last_draw = now;
            dirty = false;
        }
    }
    return 0;
}

}  // namespace

int run_top(const Args& args) {
    Args with = args;
    with.push_back("--full-screen");
    return run_watch(with);
}

int run_watch(const Args& args) {
    CliOptions options;
    if (parse_device_command(args, {{"--full-screen"}, {"--count", "--channel"}}, watch_usage, options)) return 0;
    if (!options.positionals.empty()) throw UsageError{"unexpected argument " + options.positionals.front()};
    const bool full_screen = options.flags.count("--full-screen") > 0;
    if (full_screen && options.json) throw UsageError{"--full-screen and --json exclude each other"};
    if (full_screen && options.values.count("--count")) throw UsageError{"--full-screen runs until q: no --count"};
    if (full_screen && !FullScreen::is_terminal()) throw UsageError{"--full-screen needs a terminal (use watch without it)"};
    std::uint64_t count = 0;
    if (const auto it = options.values.find("--count"); it != options.values.end()) count = parse_count("--count", it->second);
    std::optional<std::string> channel;
    if (const auto it = options.values.find("--channel"); it != options.values.end()) {
        check_terminal_id("--channel", it->second);
        channel = it->second;
    }

    install_interrupt_handler();
    // Before the client: its dispatch thread pushes into the inbox until the
    // client is destroyed, so the inbox must outlive it.
    Inbox<SampleDtu> inbox;
    Result<SubscriptionId> sub = make_error(ErrorCode::unavailable, "not subscribed");
    auto client = connect_client(options, [&](Client& c) {
        sub = c.subscribe_samples(
            options.device, [&](const SampleDtu& s) { inbox.push(s); }, channel);
    });
    if (!sub) {
        std::fprintf(stderr, "nclink watch: %s\n", sub.error().describe().c_str());
        return 1;
    }
    // Column names come from the model; without one the points are p1, p2, ...
    std::map<std::string, std::vector<std::string>> points;
    if (!options.json) {
        if (auto model = client->probe(options.device); model.ok())
            for (auto& c : find_channels(*model)) points[c.id] = std::move(c.points);
        else std::fprintf(stderr, "nclink watch: no model (%s); columns are numbered\n", model.error().describe().c_str());
    }
    if (full_screen) return run_full_screen(options, inbox, std::move(points));
    Table table(std::move(points));
    std::uint64_t seen = 0;
    while (count == 0 || seen < count) {
        auto dtu = inbox.pop(std::chrono::steady_clock::time_point::max());
        if (!dtu) break;  // Ctrl-C
        ++seen;
        if (options.json) {
            std::printf("%s\n", encode(*dtu).c_str());
            std::fflush(stdout);
        } else {
            table.print(*dtu);
        }
    }
    return 0;
}

}  // namespace nclink::cli
