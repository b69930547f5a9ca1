// Runs a libFuzzer target without libFuzzer (g++ builds, ctest smoke runs):
// every file of the corpus directory, then N deterministic mutations of them
// (bit flips, byte insertions/deletions, truncations, splices). A crash or a
// sanitizer report fails the test; the seed is fixed so failures reproduce.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::vector<std::string> load_corpus(const std::filesystem::path& dir) {
    std::vector<std::string> inputs;
    std::vector<std::filesystem::path> files;
    if (std::filesystem::is_directory(dir))
        for (const auto& entry : std::filesystem::directory_iterator(dir))
            if (entry.is_regular_file()) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
        std::ifstream in(file, std::ios::binary);
        inputs.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    return inputs;
}

std::string mutate(std::string input, const std::vector<std::string>& corpus, std::mt19937& rng) {
    static const char* const kTokens[] = {"{",       "}",       "[",  "]",     "\"",          ":",        ",",
                                          "null",    "true",    "-1", "1e309", "\"\\u0000\"", "\xff\xfe", "\"id\"",
                                          "\"ids\"", "\"@id\"", "0",  "{}",    "[]",          "\"5-8\""};
    const int steps = 1 + static_cast<int>(rng() % 4);
    for (int s = 0; s < steps; ++s) {
        const std::size_t pos = input.empty() ? 0 : rng() % (input.size() + 1);
        switch (rng() % 6) {
            case 0:  // flip a bit
                if (!input.empty()) input[pos % input.size()] ^= static_cast<char>(1u << (rng() % 8));
                break;
            case 1:  // insert a random byte
                input.insert(input.begin() + static_cast<std::ptrdiff_t>(pos), static_cast<char>(rng() & 0xff));
                break;
            case 2:  // delete a run
                if (!input.empty()) input.erase(pos % input.size(), 1 + rng() % 8);
                break;
            case 3:  // truncate
                input.resize(pos);
                break;
            case 4:  // insert a JSON-ish token
                input.insert(pos, kTokens[rng() % (sizeof kTokens / sizeof *kTokens)]);
                break;
            default:  // splice with another corpus entry
                if (!corpus.empty()) {
                    const std::string& other = corpus[rng() % corpus.size()];
                    const std::size_t from = other.empty() ? 0 : rng() % other.size();
                    input.insert(pos, other.substr(from, rng() % 64));
                }
                break;
        }
    }
    return input;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s CORPUS_DIR [MUTATIONS]\n", argv[0]);
        return 2;
    }
    const auto corpus = load_corpus(argv[1]);
    const long mutations = argc > 2 ? std::strtol(argv[2], nullptr, 10) : 1000;
    for (const auto& input : corpus) LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
    std::mt19937 rng(20221012);  // fixed: the standard's publication date
    std::vector<std::string> seeds = corpus;
    if (seeds.empty()) seeds.emplace_back("{}");
    for (long i = 0; i < mutations; ++i) {
        const std::string input = mutate(seeds[rng() % seeds.size()], seeds, rng);
        LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
    }
    std::printf("fuzz smoke: %zu corpus inputs and %ld mutations ran clean\n", corpus.size(), mutations);
    return 0;
}
