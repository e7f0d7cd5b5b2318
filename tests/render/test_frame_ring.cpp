// The producer/consumer frame ring: order, bounded memory, close and abort.
#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "render/frame_ring.hpp"

using namespace sinew;

TEST_CASE("frame ring: 200 frames pass through 3 slots in order") {
  FrameRing ring(3, 4);
  std::vector<int> seen;
  std::thread consumer([&] {
    while (const uint8_t* p = ring.next()) {
      seen.push_back(p[0] | p[1] << 8);
      ring.release();
    }
  });
  for (int i = 0; i < 200; ++i) {
    uint8_t* slot = ring.acquire();
    REQUIRE(slot);
    slot[0] = uint8_t(i & 0xff), slot[1] = uint8_t(i >> 8);
    ring.publish();
  }
  ring.close();
  consumer.join();
  REQUIRE(seen.size() == 200);
  for (int i = 0; i < 200; ++i) CHECK(seen[i] == i);
}

TEST_CASE("frame ring: the producer waits once every slot is taken (memory stays bounded)") {
  FrameRing ring(2, 1);
  for (int i = 0; i < 2; ++i) {
    REQUIRE(ring.acquire());
    ring.publish();
  }
  std::atomic<bool> got_third{false};
  std::thread producer([&] {
    if (ring.acquire()) got_third = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  CHECK(!got_third);  // blocked: both slots hold unconsumed frames
  REQUIRE(ring.next());
  ring.release();
  producer.join();
  CHECK(got_third);
}

TEST_CASE("frame ring: abort wakes a waiting consumer and refuses the producer") {
  FrameRing ring(2, 1);
  std::atomic<bool> woke{false};
  std::thread consumer([&] {
    if (!ring.next()) woke = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ring.abort();
  consumer.join();
  CHECK(woke);
  CHECK(ring.acquire() == nullptr);
}
