// What the bridge's integration tests share: validation of a served document
// with xmllint against the MTConnect 1.4 schemas, percent-encoding of a query
// value, reading an attribute.
#pragma once

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <string>

namespace nclink::test {

/// True when `xml` validates against MTConnect{kind}_1.4_1.0.xsd (kind =
/// Devices, Streams, Error); warns and passes when the schemas or xmllint are absent.
inline bool validates(const std::string& xml, const std::string& kind) {
    // CI lays shared/ beside the source tree; NCLINK_SHARED_DIR in the environment overrides it.
    const char* env = std::getenv("NCLINK_SHARED_DIR");
    const std::string xsd =
        std::string(env && *env ? env : NCLINK_SHARED_DIR) + "/interop/mtconnect-schema/MTConnect" + kind + "_1.4_1.0.xsd";
    if (!std::filesystem::exists(xsd) || std::system("command -v xmllint >/dev/null 2>&1") != 0) {
        WARN("MTConnect schemas or xmllint absent: not validated against " << xsd);
        return true;
    }
    const auto file = std::filesystem::temp_directory_path() / ("nclink-bridge-itest-" + std::to_string(::getpid()) + ".xml");
    std::ofstream(file) << xml;
    const std::string cmd = "xmllint --nonet --noout --schema " + xsd + " " + file.string() + " >/dev/null 2>&1";
    const int rc = std::system(cmd.c_str());
    if (rc != 0) std::cerr << "invalid " << kind << ":\n" << xml.substr(0, 4000) << "\n";
    std::filesystem::remove(file);
    return rc == 0;
}

/// A query value as a client sends it (RFC 3986 percent-encoding).
inline std::string encoded(const std::string& text) {
    std::string out;
    for (unsigned char c : text) {
        if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~' || c == '/') out += static_cast<char>(c);
        else out += fmt::format("%{:02X}", c);
    }
    return out;
}

/// The first value of attribute `name` in `xml` ("" when there is none).
inline std::string attribute(const std::string& xml, const std::string& name) {
    std::smatch m;
    if (std::regex_search(xml, m, std::regex(" " + name + "=\"([^\"]*)\""))) return m[1];
    return {};
}

}  // namespace nclink::test
