// "@id"s of one client's requests: "{ex}-{counter}-{salt}". The salt (random
// per client instance) keeps a restarted application with the same ex_cid
// from reusing ids an adapter may still hold in its de-duplication window.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

namespace nclink::client_detail {

class RequestIds {
public:
    explicit RequestIds(std::string ex);
    std::string next();
    const std::string& salt() const noexcept { return salt_; }

private:
    std::string ex_;
    std::string salt_;
    std::atomic<std::uint64_t> counter_{0};
};

}  // namespace nclink::client_detail
