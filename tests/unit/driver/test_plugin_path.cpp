// A plugin named relative to its configuration file loads when the
// configuration is given as a bare file name (docs/configuration.md: paths
// are relative to the file), and a missing plugin says where it looked.
#include <nclink/adapter_config.hpp>
#include <nclink/driver_plugin_loader.hpp>

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace nclink;

TEST_CASE("a plugin next to a configuration named without a directory loads") {
    const auto dir = std::filesystem::temp_directory_path() / "nclink-plugin-path";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    std::filesystem::copy_file(std::string(NCLINK_TEST_PLUGIN_DIR) + "/c_counter.so", dir / "acme-lathe.so");
    const auto before = std::filesystem::current_path();
    std::filesystem::current_path(dir);
    for (const char* written : {"acme-lathe.so", "./acme-lathe.so"}) {
        std::ofstream(dir / "adapter.json") << Json{{"model", "m.json"}, {"driver", {{"plugin", written}}}}.dump();
        auto config = load_adapter_config("adapter.json");
        REQUIRE(config.ok());
        auto loaded = load_driver_plugin(config->driver_plugin, nullptr, Logger{});
        INFO(written << ": " << (loaded.ok() ? "" : loaded.error().message));
        CHECK(loaded.ok());
    }
    std::filesystem::current_path(before);
    std::filesystem::remove_all(dir);
}

TEST_CASE("a plugin path that names no file says so and how it was resolved") {
    auto loaded = load_driver_plugin("/nonexistent/dir/acme-lathe.so", nullptr, Logger{});
    REQUIRE_FALSE(loaded.ok());
    CHECK(loaded.error().message ==
          "driver plugin /nonexistent/dir/acme-lathe.so does not exist (a relative driver.plugin is resolved against "
          "the directory of the configuration file)");
}
