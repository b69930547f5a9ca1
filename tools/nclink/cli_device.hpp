// What the device subcommands (probe, query, set, watch, state) share:
// connecting a Client from the command-line options, Ctrl-C, walking a
// probe (model) JSON, and time formatting.
#pragma once

#include "cli_options.hpp"

#include <nclink/client.hpp>

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace nclink::cli {

int run_probe(const Args& args);
int run_query(const Args& args);
int run_set(const Args& args);
int run_watch(const Args& args);
int run_top(const Args& args);        ///< watch --full-screen
int run_probe_set(const Args& args);  // cmd_probe_set.cpp
extern const char* const probe_set_usage;
int run_state(const Args& args);
extern const char* const probe_usage;
extern const char* const query_usage;
extern const char* const set_usage;
extern const char* const watch_usage;
extern const char* const state_usage;
int run_events(const Args& args);  // cmd_events.cpp
extern const char* const events_usage;
int run_call(const Args& args);     // cmd_call.cpp
int run_control(const Args& args);  // cmd_control.cpp
extern const char* const call_usage;
extern const char* const control_usage;
/// For call/control: the device as --device or the first positional.
bool parse_method_command(const Args& args, const char* usage, CliOptions& out, const OptionSpec& spec = {});

/// Parses the options, prints `usage` for --help (returns true = done), and
/// checks --device / --client-id. Fills in the default client id.
bool parse_device_command(const Args& args, const OptionSpec& spec, const char* usage, CliOptions& out);

/// A started, connected client; registration is sent but not waited for
/// (without an agent nobody answers). Throws std::runtime_error when the
/// broker cannot be reached within the timeout (exit 1). `before_start`
/// subscribes what must be in place when the link comes up: with
/// --persistent the broker delivers what it kept right after connecting.
std::unique_ptr<Client> connect_client(const CliOptions& options, const std::function<void(Client&)>& before_start = {});

/// Set by SIGINT/SIGTERM once install_interrupt_handler() ran.
bool interrupted();
void install_interrupt_handler();

/// "2026-11-21T10:00:00.123Z" for ms since the epoch.
std::string format_time_ms(std::int64_t ms);

/// Sample channels of a probe: id, intervals, point ids (in channel order).
struct ChannelInfo {
    std::string id;
    std::string name;
    double sample_interval = 0;
    double upload_interval = 0;
    std::vector<std::string> points;
};
std::vector<ChannelInfo> find_channels(const Json& model);

/// A string member, also under alias spellings.
std::string string_member(const Json& object, std::initializer_list<const char*> keys);

}  // namespace nclink::cli
