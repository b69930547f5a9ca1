// ModelCache (nclink/model_cache.hpp): a gateway's machines of one model file
// share one parsed model and its value rules, and a changed or released file
// is parsed again.
#include "model_test_util.hpp"

#include <nclink/model_cache.hpp>

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <random>

using namespace nclink;
using namespace nclink::test;

namespace {

struct Scratch {
    Scratch() : dir(std::filesystem::temp_directory_path() / ("nclink-model-cache-" + std::to_string(std::random_device{}()))) {
        std::filesystem::create_directories(dir);
    }
    ~Scratch() {
        std::error_code ec;
        std::filesystem::remove_all(dir, ec);
    }
    std::string copy_of(const std::string& model) const {
        const auto to = dir / model;
        std::filesystem::copy_file(model_path(model), to, std::filesystem::copy_options::overwrite_existing);
        return to.string();
    }
    std::filesystem::path dir;
};

}  // namespace

TEST_CASE("model cache: one parse while the model is in use, the same objects for every loader") {
    ModelCache cache;
    const Scratch scratch;
    const std::string path = scratch.copy_of("sim-mill.json");
    LoadResult first = cache.load(path);
    REQUIRE(first.ok());
    LoadResult second = cache.load(path);
    REQUIRE(second.ok());
    CHECK(cache.parses() == 1);
    CHECK(first.model.get() == second.model.get());
    CHECK(first.document.get() == second.document.get());
    CHECK(second.problems.size() == first.problems.size());
    // The same as an uncached load of the file.
    CHECK(*second.model == *load_model_file(path).model);

    // Another file is another model.
    const LoadResult other = cache.load(scratch.copy_of("appendix-b-corrected.json"));
    REQUIRE(other.ok());
    CHECK(other.model.get() != first.model.get());
    CHECK(cache.parses() == 2);
}

TEST_CASE("model cache: a loader that keeps only the model still shares it with the next one") {
    // A simulated machine's driver keeps the model and drops the document:
    // the next machine of the same file must still get the one parse.
    ModelCache cache;
    const Scratch scratch;
    const std::string path = scratch.copy_of("sim-mill.json");
    std::shared_ptr<const Model> kept = cache.load(path).model;
    REQUIRE(kept);
    std::shared_ptr<const std::string> document;
    {
        const LoadResult next = cache.load(path);
        REQUIRE(next.ok());
        CHECK(cache.parses() == 1);
        CHECK(next.model.get() == kept.get());
        REQUIRE(next.document);
        CHECK_FALSE(next.document->empty());
        document = next.document;
    }
    // And the other way round: the document alone keeps the entry too.
    const Model* const before = kept.get();
    kept.reset();
    const LoadResult again = cache.load(path);
    REQUIRE(again.ok());
    CHECK(cache.parses() == 1);
    CHECK(again.model.get() == before);
    CHECK(again.document.get() == document.get());
}

TEST_CASE("model cache: a changed file is parsed again, and so is one nobody holds") {
    ModelCache cache;
    const Scratch scratch;
    const std::string path = scratch.copy_of("sim-mill.json");
    LoadResult first = cache.load(path);
    REQUIRE(first.ok());
    // A new version deployed under the same name: another size.
    {
        std::ofstream out(path, std::ios::app);
        out << "\n\n";
    }
    LoadResult changed = cache.load(path);
    REQUIRE(changed.ok());
    CHECK(cache.parses() == 2);
    CHECK(changed.model.get() != first.model.get());
    CHECK(changed.document->size() == first.document->size() + 2);

    // The cache holds nothing alive by itself.
    const std::weak_ptr<const Model> gone = changed.model;
    first = LoadResult{};
    changed = LoadResult{};
    CHECK(gone.expired());
    CHECK(cache.load(path).ok());
    CHECK(cache.parses() == 3);
}

TEST_CASE("model cache: a file that cannot be read is the loader's fatal problem, never kept") {
    ModelCache cache;
    const Scratch scratch;
    const std::string path = (scratch.dir / "missing.json").string();
    const LoadResult missing = cache.load(path);
    CHECK_FALSE(missing.ok());
    CHECK(missing.count(Severity::fatal) >= 1);
    std::filesystem::copy_file(model_path("sim-mill.json"), path);
    CHECK(cache.load(path).ok());
    CHECK(cache.parses() == 2);
}

TEST_CASE("model cache: value rules built once per model while in use") {
    ModelCache cache;
    const LoadResult loaded = cache.load(model_path("sim-mill.json"));
    REQUIRE(loaded.ok());
    const auto a = cache.rules(loaded.model);
    const auto b = cache.rules(loaded.model);
    REQUIRE(a);
    CHECK(a.get() == b.get());
    const LoadResult other = load_model_file(model_path("appendix-b-corrected.json"));
    CHECK(cache.rules(other.model).get() != a.get());
    CHECK(cache.rules(nullptr) != nullptr);  // no model: rules that let every value pass
}
