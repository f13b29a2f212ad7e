// Runs the CanBus conformance suite on the backends that need no hardware: the in-process
// emulated bus and the loopback UDP bus. SocketCAN and gs_usb instantiate it in their own files.
#include "tests/rig/can_bus_conformance.h"

#include <memory>
#include <string_view>
#include <thread>

#include "rig/emulated_bus.h"
#include "rig/udp_bus.h"

namespace hilrig::rig {
namespace {

class EmulatedBackend final : public CanBusBackend {
 public:
  std::string Name() const override { return "emulated bus"; }
  std::optional<std::string> SkipReason() const override { return std::nullopt; }

  Result<std::vector<std::unique_ptr<CanBus>>> MakeEndpoints(std::size_t count) override {
    std::vector<std::unique_ptr<CanBus>> endpoints;
    for (std::size_t k = 0; k < count; ++k) {
      endpoints.push_back(bus_.Connect("node" + std::to_string(k)));
    }
    return endpoints;
  }

  std::int64_t NowNs() const override { return now_ns_; }
  void Advance(std::int64_t dt_ns) override { now_ns_ += dt_ns; }

  // Through the medium rather than an endpoint: the bus's own fault injection path.
  Result<void> InjectErrorFrame(CanBus&, const CanFrame& error_frame) override {
    return bus_.InjectErrorFrame(error_frame, now_ns_);
  }

 private:
  EmulatedBus bus_;
  std::int64_t now_ns_ = 0;
};

// Real sockets, so time is only a counter and Advance yields to let the kernel deliver.
class UdpBackend final : public CanBusBackend {
 public:
  std::string Name() const override { return "loopback UDP bus"; }
  std::optional<std::string> SkipReason() const override { return std::nullopt; }

  Result<std::vector<std::unique_ptr<CanBus>>> MakeEndpoints(std::size_t count) override {
    auto group = OpenUdpBusGroup(count);
    if (!group) return group.error();
    std::vector<std::unique_ptr<CanBus>> endpoints;
    for (std::unique_ptr<UdpBus>& endpoint : group.value())
      endpoints.push_back(std::move(endpoint));
    return endpoints;
  }

  std::int64_t NowNs() const override { return now_ns_; }
  void Advance(std::int64_t dt_ns) override {
    now_ns_ += dt_ns;
    std::this_thread::yield();
  }

 private:
  std::int64_t now_ns_ = 0;
};

INSTANTIATE_TEST_SUITE_P(
    InProcess, CanBusConformanceTest,
    ::testing::Values(CanBusBackendParam{"emulated",
                                         [] { return std::make_unique<EmulatedBackend>(); }},
                      CanBusBackendParam{"udp", [] { return std::make_unique<UdpBackend>(); }}),
    CanBusBackendParamName);

// The tests live in can_bus_conformance.cc. Were it missing from this binary, the
// instantiation above would run nothing and look like a pass.
TEST(CanBusConformanceSuiteTest, SuiteIsLinkedIn) {
  const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
  int tests = 0;
  for (int i = 0; i < unit.total_test_suite_count(); ++i) {
    const ::testing::TestSuite& suite = *unit.GetTestSuite(i);
    if (std::string_view(suite.name()) == "InProcess/CanBusConformanceTest") {
      tests += suite.total_test_count();
    }
  }

  EXPECT_GT(tests, 0) << "tests/rig/can_bus_conformance.cc is not linked into this test binary; "
                         "add it to rig_tests in tests/CMakeLists.txt";
}

}  // namespace
}  // namespace hilrig::rig
