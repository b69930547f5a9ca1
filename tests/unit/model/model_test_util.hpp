// Helpers shared by the model tests.
#pragma once

#include <nclink/model.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace nclink::test {

inline std::string models_dir() { return NCLINK_MODELS_DIR; }
inline std::string model_path(const std::string& name) { return models_dir() + "/" + name; }

/// Problems with the given severity and pointer.
inline std::vector<Problem> problems_at(const LoadResult& r, Severity s, const std::string& ptr) {
    std::vector<Problem> out;
    for (const auto& p : r.problems)
        if (p.severity == s && p.pointer == ptr) out.push_back(p);
    return out;
}

inline bool has_problem(const LoadResult& r, Severity s, const std::string& ptr) { return !problems_at(r, s, ptr).empty(); }

/// Every .json file directly in `dir`, sorted.
inline std::vector<std::filesystem::path> json_files(const std::string& dir) {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.is_regular_file() && e.path().extension() == ".json") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

inline std::string describe(const LoadResult& r) {
    std::string out;
    for (const auto& p : r.problems)
        out += std::string(to_string(p.severity)) + " " + (p.pointer.empty() ? "/" : p.pointer) + ": " + p.message + "\n";
    return out;
}

}  // namespace nclink::test
