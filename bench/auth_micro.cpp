// Cost of signed fleet traffic per message (docs/security.md): signing and
// verifying (HMAC-SHA-512-256 over channel, envelope fields and payload) and
// the whole wrap / check / unwrap through LcmFleet's envelope, for the sizes
// of the fleet's messages: an agent state (~80 B), a full data batch (~2.4
// KB) and a tick reply with custody keys (~17 KB).
#include <benchmark/benchmark.h>

#include <array>
#include <memory>
#include <vector>

#include "gather_agent/transport/fleet_auth.hpp"
#include "gather_agent/transport/lcm_fleet.hpp"

namespace {

using namespace gather::agent;

const std::vector<std::string> kChannels{"GATHER_STATE"};

void BM_Sign(benchmark::State& state) {
  FleetAuth a(generate_fleet_key(), kChannels, kMaxTeam + 1);
  std::vector<uint8_t> payload(static_cast<std::size_t>(state.range(0)), 0x42);
  EnvelopeHead h;
  uint8_t mac[kMacBytes];
  for (auto _ : state) {
    a.sign("GATHER_STATE", 3, payload.data(), payload.size(), h, mac);
    benchmark::DoNotOptimize(mac);
  }
  state.SetBytesProcessed(state.iterations() * state.range(0));
}

// Verifies messages signed beforehand (in batches, so that the timer is
// paused once per batch, not per message), each with a newer counter.
void BM_Verify(benchmark::State& state) {
  constexpr std::size_t kBatch = 4096;
  const FleetKey k = generate_fleet_key();
  FleetAuth tx(k, kChannels, kMaxTeam + 1);
  std::vector<uint8_t> payload(static_cast<std::size_t>(state.range(0)), 0x42);
  std::vector<EnvelopeHead> heads(kBatch);
  std::vector<std::array<uint8_t, kMacBytes>> macs(kBatch);
  for (std::size_t i = 0; i < kBatch; ++i)
    tx.sign("GATHER_STATE", 3, payload.data(), payload.size(), heads[i], macs[i].data());
  auto rx = std::make_unique<FleetAuth>(k, kChannels, kMaxTeam + 1);
  std::size_t i = 0;
  for (auto _ : state) {
    if (i == kBatch) {  // a new batch: newer counters for the same receiver
      state.PauseTiming();
      for (std::size_t j = 0; j < kBatch; ++j)
        tx.sign("GATHER_STATE", 3, payload.data(), payload.size(), heads[j], macs[j].data());
      i = 0;
      state.ResumeTiming();
    }
    benchmark::DoNotOptimize(rx->verify("GATHER_STATE", heads[i], payload.data(), payload.size(), macs[i].data()));
    ++i;
  }
  if (rx->counters().total() != 0) state.SkipWithError("a good message was rejected");
  state.SetBytesProcessed(state.iterations() * state.range(0));
}

}  // namespace

BENCHMARK(BM_Sign)->Arg(80)->Arg(2400)->Arg(17000);
BENCHMARK(BM_Verify)->Arg(80)->Arg(2400)->Arg(17000);
BENCHMARK_MAIN();
