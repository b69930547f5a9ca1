// Helpers shared by the mapping tests: models, fixed options, and running the
// real consumers (xmllint with the MTConnect/OPC UA schemas, node-opcua).
#pragma once

#include <nclink/mapping.hpp>
#include <nclink/model.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

namespace nclink::test {

inline std::string mapping_model_path(const std::string& name) { return std::string(NCLINK_MODELS_DIR) + "/" + name; }

inline std::shared_ptr<const Model> load_mapping_model(const std::string& name) {
    const LoadResult r = load_model_file(mapping_model_path(name));
    REQUIRE(r.ok());
    return r.model;
}

inline std::shared_ptr<const Model> parse_mapping_model(const std::string& text) {
    const LoadResult r = parse_model(text);
    INFO(text);
    REQUIRE(r.ok());
    return r.model;
}

/// Options with a fixed creation time, so documents are reproducible.
inline MappingOptions fixed_options(OpcUaProfile profile = OpcUaProfile::basic) {
    MappingOptions o;
    o.creation_time = "2024-01-01T00:00:00Z";
    o.opcua_profile = profile;
    return o;
}

/// The shared interop fixtures (schemas, nodesets, tools): the environment
/// variable NCLINK_INTEROP_DIR, else <source>/../shared/interop; "" when
/// neither exists.
inline std::string interop_dir() {
    namespace fs = std::filesystem;
    if (const char* env = std::getenv("NCLINK_INTEROP_DIR"); env != nullptr && *env != '\0')
        return fs::is_directory(env) ? std::string(env) : std::string();
#ifdef NCLINK_INTEROP_DIR
    if (fs::is_directory(NCLINK_INTEROP_DIR)) return NCLINK_INTEROP_DIR;
#endif
    return {};
}

/// tools/nclink-opcua/node_modules when it was installed, else "".
inline std::string node_modules_dir() {
#ifdef NCLINK_OPCUA_TOOL_DIR
    const std::string dir = std::string(NCLINK_OPCUA_TOOL_DIR) + "/node_modules";
    if (std::filesystem::is_directory(dir + "/node-opcua-address-space")) return dir;
#endif
    return {};
}

struct CommandRun {
    int status = -1;
    std::string output;  ///< standard output and error
};

inline CommandRun run_command(const std::string& command) {
    CommandRun run;
    std::FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
    if (pipe == nullptr) return run;
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) run.output.append(buffer, n);
    const int status = ::pclose(pipe);
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return run;
}

inline bool have_program(const std::string& name) { return run_command("command -v " + name + " >/dev/null").status == 0; }

/// A scratch directory below the build tree.
inline std::string scratch_dir() {
    const std::string dir = std::string(NCLINK_BINARY_DIR) + "/test-mapping";
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::string write_scratch(const std::string& name, const std::string& text) {
    const std::string path = scratch_dir() + "/" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    return path;
}

inline std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// `xmllint --schema` exit status and messages for a document.
inline CommandRun xmllint_schema(const std::string& schema, const std::string& file) {
    return run_command("xmllint --nonet --noout --schema '" + schema + "' '" + file + "'");
}

}  // namespace nclink::test
