// Cost of signed fleet traffic per message (docs/security.md), for the sizes
// of the fleet's messages: an agent state (~80 B), a full data batch (~2.4
// KB) and a tick reply with custody keys (~17 KB):
//  - one MAC (the robot link: HMAC-SHA-512-256 over channel, envelope fields
//    and payload), signed and verified;
//  - per-link tags (the fleet): signed for 1, 3, 21 and 301 receivers (a
//    worker's, a collector's, the OC's broadcast to 20 and to 300 agents),
//    and one receiver's check of its own tag among 21;
//  - Ed25519 (libsodium crypto_sign), signed and verified: what the OC's
//    broadcasts would cost as public-key signatures instead.
#include <benchmark/benchmark.h>

#include <sodium.h>

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

// Receivers -1 (the OC), 0, 1, ...: `n` of them.
std::vector<int16_t> receivers(int64_t n) {
  std::vector<int16_t> r;
  for (int64_t i = 0; i < n; ++i) r.push_back(static_cast<int16_t>(i - 1));
  return r;
}

// A message of range(0) bytes signed by the OC (the master) for range(1) receivers.
void BM_SignTagged(benchmark::State& state) {
  FleetAuth a(KeyRing(generate_fleet_key()), PerLinkTags{}, kChannels, kMaxTeam + 1);
  std::vector<uint8_t> payload(static_cast<std::size_t>(state.range(0)), 0x42);
  std::vector<int16_t> to = receivers(state.range(1) + 1);
  to.erase(to.begin());  // not to itself
  std::vector<uint8_t> tags(to.size() * kTagBytes);
  EnvelopeHead h;
  if (!a.sign_tagged("GATHER_STATE", kOc, payload.data(), payload.size(), to.data(), to.size(), h, tags.data()))
    state.SkipWithError("no key");
  for (auto _ : state) {
    a.sign_tagged("GATHER_STATE", kOc, payload.data(), payload.size(), to.data(), to.size(), h, tags.data());
    benchmark::DoNotOptimize(tags.data());
  }
  state.SetBytesProcessed(state.iterations() * state.range(0));
}

// Agent 7 checks its own tag of a message the OC signed for agents 0..19.
void BM_VerifyTagged(benchmark::State& state) {
  constexpr std::size_t kBatch = 4096;
  const FleetKey master = generate_fleet_key();
  FleetAuth tx(KeyRing(master), PerLinkTags{}, kChannels, kMaxTeam + 1);
  std::vector<uint8_t> payload(static_cast<std::size_t>(state.range(0)), 0x42);
  std::vector<int16_t> to = receivers(21);
  to.erase(to.begin());
  std::vector<EnvelopeHead> heads(kBatch);
  std::vector<std::vector<uint8_t>> tags(kBatch, std::vector<uint8_t>(to.size() * kTagBytes));
  auto sign_batch = [&] {
    for (std::size_t j = 0; j < kBatch; ++j)
      tx.sign_tagged("GATHER_STATE", kOc, payload.data(), payload.size(), to.data(), to.size(), heads[j],
                     tags[j].data());
  };
  sign_batch();
  std::vector<int16_t> peers{kOc};
  auto rx = std::make_unique<FleetAuth>(agent_key_ring(master, 7, peers), PerLinkTags{}, kChannels, kMaxTeam + 1);
  std::size_t i = 0;
  for (auto _ : state) {
    if (i == kBatch) {
      state.PauseTiming();
      sign_batch();
      i = 0;
      state.ResumeTiming();
    }
    benchmark::DoNotOptimize(rx->verify_tagged("GATHER_STATE", heads[i], payload.data(), payload.size(), to.data(),
                                               tags[i].data(), to.size()));
    ++i;
  }
  if (rx->counters().total() != 0) state.SkipWithError("a good message was rejected");
  state.SetBytesProcessed(state.iterations() * state.range(0));
}

void BM_Ed25519Sign(benchmark::State& state) {
  if (sodium_init() < 0) state.SkipWithError("sodium_init");
  unsigned char pk[crypto_sign_PUBLICKEYBYTES], sk[crypto_sign_SECRETKEYBYTES], sig[crypto_sign_BYTES];
  crypto_sign_keypair(pk, sk);
  std::vector<uint8_t> payload(static_cast<std::size_t>(state.range(0)), 0x42);
  for (auto _ : state) {
    crypto_sign_detached(sig, nullptr, payload.data(), payload.size(), sk);
    benchmark::DoNotOptimize(sig);
  }
  state.SetBytesProcessed(state.iterations() * state.range(0));
}

void BM_Ed25519Verify(benchmark::State& state) {
  if (sodium_init() < 0) state.SkipWithError("sodium_init");
  unsigned char pk[crypto_sign_PUBLICKEYBYTES], sk[crypto_sign_SECRETKEYBYTES], sig[crypto_sign_BYTES];
  crypto_sign_keypair(pk, sk);
  std::vector<uint8_t> payload(static_cast<std::size_t>(state.range(0)), 0x42);
  crypto_sign_detached(sig, nullptr, payload.data(), payload.size(), sk);
  for (auto _ : state)
    if (crypto_sign_verify_detached(sig, payload.data(), payload.size(), pk) != 0) state.SkipWithError("bad");
  state.SetBytesProcessed(state.iterations() * state.range(0));
}

}  // namespace

BENCHMARK(BM_Sign)->Arg(80)->Arg(2400)->Arg(17000);
BENCHMARK(BM_Verify)->Arg(80)->Arg(2400)->Arg(17000);
BENCHMARK(BM_SignTagged)->Args({80, 1})->Args({80, 3})->Args({80, 21})->Args({80, 301})->Args({2400, 3});
BENCHMARK(BM_VerifyTagged)->Arg(80)->Arg(2400);
BENCHMARK(BM_Ed25519Sign)->Arg(80)->Arg(2400);
BENCHMARK(BM_Ed25519Verify)->Arg(80)->Arg(2400);
BENCHMARK_MAIN();
