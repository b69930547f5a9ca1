// `nclink control [--device] DEV METHOD stop|resume|cancel [--call ID]`:
// one Method/Control request; prints OK or the NG answer.
#include "cli_device.hpp"

#include <cstdio>
#include <optional>

namespace nclink::cli {

const char* const control_usage =
    "usage: nclink control [options] DEV METHOD stop|resume|cancel\n"
    "       nclink control --device DEV [options] METHOD stop|resume|cancel\n"
    "  Pauses (stop), resumes or cancels the running calls of METHOD\n"
    "  (Method/Control): this client id's own calls, else everybody's.\n"
    "  --call ID   only the call whose Method/Call @id is ID (see `nclink call --json`)\n"
    "  Prints OK, or NG with the error (202: the method is not running).\n"
    "  Exit status: 0 OK, 1 NG or no answer, 2 usage error.\n" NCLINK_CLI_GLOBAL_OPTIONS;

int run_control(const Args& args) {
    CliOptions options;
    Args rest;
    std::optional<std::string> call;
    for (std::size_t i = 0; i < args.size(); ++i) {  // --call is this command's own option
        if (args[i] == "--call") {
            if (i + 1 >= args.size()) throw UsageError{"--call needs a value"};
            call = args[++i];
        } else if (args[i].rfind("--call=", 0) == 0) {
            call = args[i].substr(7);
        } else {
            rest.push_back(args[i]);
        }
    }
    if (parse_method_command(rest, control_usage, options)) return 0;
    if (options.positionals.size() != 2) throw UsageError{"expected METHOD and an action"};
    const std::string& method = options.positionals[0];
    const std::string& action_text = options.positionals[1];
    Client::MethodAction action = Client::MethodAction::stop;
    if (action_text == "stop") action = Client::MethodAction::stop;
    else if (action_text == "resume") action = Client::MethodAction::resume;
    else if (action_text == "cancel") action = Client::MethodAction::cancel;
    else throw UsageError{"the action is stop, resume or cancel, not \"" + action_text + "\""};
    RequestOptions request;
    if (call) request.private_info = Json{{"call", *call}};
    auto client = connect_client(options);
    auto answer = client->control_method(options.device, method, action, request);
    if (options.json) {
        Json out{{"id", method}, {"action", action_text}, {"code", answer ? "OK" : "NG"}};
        if (!answer) {
            out["error"] = to_int(answer.error().code);
            out["message"] = answer.error().message;
        }
        std::printf("%s\n", out.dump(-1, ' ', false, Json::error_handler_t::replace).c_str());
    } else if (answer) {
        std::printf("OK\n");
    } else {
        std::printf("%s\n", answer.error().message.c_str());
    }
    return answer ? 0 : 1;
}

}  // namespace nclink::cli
