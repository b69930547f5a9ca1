// A C++ driver exported as a plugin with NCLINK_EXPORT_DRIVER; it does not
// link libnclink.
#include <nclink/driver_plugin_export.hpp>

namespace {

class EchoDriver final : public nclink::Driver {
public:
    nclink::DriverInfo info() const override { return {"cpp-echo", "2.0", true}; }

    nclink::Result<void> open(const nclink::DriverContext& context) override {
        prefix_ = context.config.value("prefix", std::string("v:"));
        if (context.config.value("refuse", false)) return nclink::make_error(nclink::ErrorCode::unavailable, "told to refuse");
        context.logger.info("echo driver open, prefix {}", prefix_);
        return nclink::ok_result();
    }

    nclink::Result<void> bind(const std::vector<nclink::BindPoint>& points, std::vector<nclink::PointHandle>& handles) override {
        for (std::size_t i = 0; i < points.size(); ++i)
            if (points[i].id == "h") handles[i] = 7;
        return nclink::ok_result();
    }

    void read(const std::vector<nclink::PointRef>& points, std::vector<nclink::Result<nclink::Json>>& results) override {
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (points[i].id == "h") results[i] = nclink::Json(points[i].handle);
            else if (points[i].id == "vendor") results[i] = nclink::vendor_error(-3, "coolant low");
            else if (points[i].kind == nclink::DataKind::list) results[i] = nclink::Json::array({1, 2, 3});
            else results[i] = nclink::Json(prefix_ + points[i].id);
        }
    }

    nclink::Result<void> write(const nclink::WriteRequest& request) override {
        if (!request.new_value.is_number()) return nclink::make_error(nclink::ErrorCode::value_type, "numbers only");
        return nclink::ok_result();
    }

    nclink::Result<nclink::Json> run_method(const nclink::PointRef& method, const nclink::Json& args,
                                            nclink::MethodControl& control) override {
        control.progress(100);
        return nclink::Json{{"method", method.id}, {"args", args}};
    }

    nclink::MachineLinkStatus link() const override { return {nclink::MachineLink::disconnected, "E-stop"}; }

private:
    std::string prefix_;
};

}  // namespace

NCLINK_EXPORT_DRIVER(EchoDriver)
