// `nclink call [--device] DEV METHOD [ARGS_JSON]`: one Method/Call; prints
// each Method/Status (a progress bar on a terminal, a line otherwise, nothing
// with --no-progress), then the Method/Result. Ctrl-C asks the adapter to
// cancel the call.
#include "cli_device.hpp"
#include "progress.hpp"

#include <chrono>
#include <cstdio>
#include <future>
#include <mutex>
#include <optional>
#include <unistd.h>

namespace nclink::cli {

const char* const call_usage =
    "usage: nclink call [options] DEV METHOD [ARGS_JSON]\n"
    "       nclink call --device DEV [options] METHOD [ARGS_JSON]\n"
    "  Calls a METHOD of the device's model (Method/Call) and follows it: a\n"
    "  progress bar on a terminal, one `status PHASE PERCENT` line per\n"
    "  Method/Status otherwise (none with --no-progress), then the result and\n"
    "  its return value. ARGS_JSON is a JSON object:\n"
    "    nclink call nclink-sim-mill-01 program_transfer '{\"source\":\"/tmp/O1234.nc\"}'\n"
    "  --timeout MS is the silence timeout: the call fails (203) when neither a\n"
    "  Method/Status nor the Method/Result arrives for that long.\n"
    "  Ctrl-C sends Method/Control cancel for the call and waits for its result.\n"
    "  --json: one JSON object per Method/Status, then the Method/Result.\n"
    "  --no-progress: neither the bar nor the status lines, only the result.\n"
    "  Exit status: 0 finished, 1 error, canceled or no answer, 2 usage error.\n" NCLINK_CLI_GLOBAL_OPTIONS;

bool parse_method_command(const Args& args, const char* usage, CliOptions& out, const OptionSpec& spec) {
    out = parse_cli_options(args, spec);
    if (out.help) {
        std::fputs(usage, stdout);
        return true;
    }
    if (out.device.empty()) {
        if (out.positionals.empty()) throw UsageError{"no device given (DEV or --device)"};
        out.device = out.positionals.front();
        out.positionals.erase(out.positionals.begin());
    }
    check_terminal_id("the device", out.device);
    if (out.client_id.empty()) out.client_id = "nclink-cli-" + std::to_string(::getpid());
    check_terminal_id("--client-id", out.client_id);
    return false;
}

namespace {

void print_line(const MethodStatus& status) {
    if (status.progress) std::printf("status %s %g%%\n", status.status.c_str(), *status.progress);
    else std::printf("status %s\n", status.status.c_str());
    std::fflush(stdout);
}

void print_result(const MethodResult& r) {
    std::printf("%s", r.result.c_str());
    if (!r.status.ok)
        std::printf(": NG %s %s", r.status.error ? std::to_string(*r.status.error).c_str() : "-",
                    r.status.reason.value_or("").c_str());
    if (r.private_info && r.private_info->is_object() && r.private_info->contains("message") &&
        (*r.private_info)["message"].is_string())
        std::printf(" (%s)", (*r.private_info)["message"].get<std::string>().c_str());
    std::printf("\n");
    if (r.return_value) std::printf("%s\n", r.return_value->dump(2, ' ', false, Json::error_handler_t::replace).c_str());
}

}  // namespace

int run_call(const Args& args) {
    CliOptions options;
    if (parse_method_command(args, call_usage, options, {{"--no-progress"}, {}})) return 0;
    if (options.positionals.empty()) throw UsageError{"no METHOD given"};
    if (options.positionals.size() > 2) throw UsageError{"too many arguments (quote ARGS_JSON as one)"};
    const std::string method = options.positionals[0];
    Json call_args = nullptr;
    if (options.positionals.size() == 2) {
        call_args = Json::parse(options.positionals[1], nullptr, false);
        if (call_args.is_discarded() || !call_args.is_object()) throw UsageError{"ARGS_JSON must be a JSON object"};
    }
    // Declared before the client: its callbacks use them until it is gone.
    std::mutex mutex;  // call_id: written on the dispatch thread, read here
    std::optional<Json> call_id;
    const ProgressMode mode = progress_mode(options.flags.count("--no-progress") > 0, options.json, stdout);
    Progress bar(mode, stdout, method);  // drawn on the dispatch thread only (on_status)
    install_interrupt_handler();
    auto client = connect_client(options);
    auto on_status = [&](const MethodStatus& status) {
        {
            std::lock_guard<std::mutex> lock(mutex);
            call_id = status.msg_id;
        }
        if (options.json) {
            std::printf("%s\n", to_json(status).dump(-1, ' ', false, Json::error_handler_t::replace).c_str());
            std::fflush(stdout);
        } else if (mode == ProgressMode::bar) {
            std::optional<double> fraction;
            if (status.progress) fraction = *status.progress / 100.0;
            bar.update(fraction, status.status);
        } else if (mode == ProgressMode::lines) {
            print_line(status);
        }
    };
    auto promise = std::make_shared<std::promise<Result<MethodResult>>>();
    auto future = promise->get_future();
    client->call_method_async(options.device, method, call_args, on_status,
                              [promise](Result<MethodResult> r) { promise->set_value(std::move(r)); });
    bool cancel_sent = false;
    while (future.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
        if (!interrupted() || cancel_sent) continue;
        cancel_sent = true;
        RequestOptions control;
        {
            std::lock_guard<std::mutex> lock(mutex);
            if (call_id) control.private_info = Json{{"call", *call_id}};
        }
        std::fprintf(stderr, "\nnclink call: cancelling %s\n", method.c_str());
        client->control_method_async(
            options.device, method, Client::MethodAction::cancel,
            [](Result<void> r) {
                if (!r) std::fprintf(stderr, "nclink call: cancel refused: %s\n", r.error().describe().c_str());
            },
            control);
    }
    auto result = future.get();
    client.reset();  // no status callback after this: the bar is ours now
    if (result && result->result == "finished" && result->status.ok) bar.update(1.0, "finished");
    bar.finish();
    if (!result) {
        std::fprintf(stderr, "nclink call: %s\n", result.error().describe().c_str());
        return 1;
    }
    if (options.json) std::printf("%s\n", to_json(*result).dump(-1, ' ', false, Json::error_handler_t::replace).c_str());
    else print_result(*result);
    return result->result == "finished" && result->status.ok ? 0 : 1;
}

}  // namespace nclink::cli
