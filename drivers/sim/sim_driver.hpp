// A simulated machine: a Driver that serves plausible, time-varying values for
// every data object of any usable model, so a vendor can run an adapter (and
// its clients) before hardware exists. The sim-mill.json model gets a richer
// simulation: a 3-axis mill running a G-code program (docs/simulator.md).
//
// Determinism: every value is a function of the seed, the model and the
// injected clock (plus the Sets, methods and alarm calls made), never of wall
// time directly. Two drivers with the same seed read at the same clock times
// answer the same values.
//
// Threading: all calls lock one mutex, so the driver is safe to call from any
// thread; info().concurrent is false all the same (the SDK serializes reads
// and writes). Methods run on the SDK's method threads beside reads: the
// short ones hold the mutex for their step; program_transfer copies without
// it, so reads and sampling go on during a transfer.
#pragma once

#include <nclink/clock.hpp>
#include <nclink/driver.hpp>
#include <nclink/model.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace nclink {

struct SimOptions {
    /// Seeds every random choice (noise, initial tables, alarms).
    std::uint64_t seed = 1;
    /// Number of elements of simulated list and dict items (tool table,
    /// parameters, ...). Items with a fixed `value` keep theirs.
    std::size_t list_size = 64;
    /// Time source; null means a SystemClock.
    std::shared_ptr<const Clock> clock;
    /// Id of the device to simulate; empty means the model's first device.
    std::string device;
    /// Mill only: the program is running (auto mode) from the start. When
    /// false the mill starts free and waits for cycle_start.
    bool autostart = true;
    /// Mill only: the controller's program directory, where program_transfer
    /// pushes to and pulls from ("" = transfers answer 202). The driver
    /// configuration key "program_dir" (given to open()) overrides it.
    std::string program_dir;
    /// Mill only: simulated speed of program_transfer, bytes per second of
    /// `clock` (0 = as fast as the disk). Configuration key "transfer_rate".
    std::uint64_t transfer_rate = 32 * 1024;
};

class SimDriver final : public Driver {
public:
    /// Never throws. A null model or an unknown device leaves the driver
    /// unusable: open() returns the reason and reads answer Unavailable.
    /// Prefer create(), which reports the problem at once.
    explicit SimDriver(std::shared_ptr<const Model> model, SimOptions options = {});
    ~SimDriver() override;
    SimDriver(const SimDriver&) = delete;
    SimDriver& operator=(const SimDriver&) = delete;

    /// The driver, or why it cannot simulate this model/device (202 or 401).
    static Result<std::unique_ptr<SimDriver>> create(std::shared_ptr<const Model> model, SimOptions options = {});

    DriverInfo info() const override;
    Result<void> open(const DriverContext& context) override;
    /// A handle per simulated item (its row) and per mill method; items the
    /// simulator does not know stay by id (their reads answer 401).
    Result<void> bind(const std::vector<BindPoint>& points, std::vector<PointHandle>& handles) override;
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override;
    /// The typed read sample channels use (a reference for vendors: the
    /// same values as read(), texts lent from a buffer kept until the next
    /// call). An unusable model or a broken link leaves the row null.
    bool read_samples(const std::vector<PointRef>& points, SampleValue* out) override;
    /// Applies request.params with parse_set/apply (all or nothing; table-19
    /// errors). `setable` is not checked again: the SDK already refused Sets
    /// on non-setable items, and tests may drive any item directly.
    Result<void> write(const WriteRequest& request) override;
    /// Mill: cycle_start, feed_hold, reset (return {"status": ...}) and
    /// program_transfer (a G-code file between program_dir and a local path,
    /// progress per KiB, pause/cancel between chunks, never a partial file;
    /// docs/simulator.md). Other models: Unavailable for methods of the
    /// model, Node not exists for unknown ids. Dispatched on the handle
    /// bind() gave the method, else on its id.
    Result<Json> run_method(const PointRef& method, const Json& args, MethodControl& control) override;
    /// True for configuration objects without a fixed value in the model (the
    /// simulator has them: tool table, parameters...); fixed values stay the SDK's.
    bool claims(std::string_view id) const override;
    MachineLinkStatus link() const override;

    /// True when the device is simulated as the mill (sim-mill.json).
    bool is_mill() const;
    /// Ids of the simulated data objects, in model order.
    std::vector<std::string> item_ids() const;
    /// Raises an alarm on every WARNING item (the mill also holds its feed).
    /// `number` is the alarm number (a string, table 14).
    void raise_alarm(const std::string& number, const std::string& text);
    /// Clears the alarm with this number, or every alarm when empty.
    void clear_alarm(std::string_view number = {});

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace nclink
