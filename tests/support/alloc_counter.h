#pragma once
// Counts heap allocations made by this thread, to prove that real-time code allocates nothing.
// Linking this file replaces the global operator new/delete of the test binary.
//
//   robossis::testing::AllocationCounter counter;
//   tick();
//   EXPECT_EQ(counter.count(), 0);

#include <cstddef>

namespace robossis::testing {

// Allocations made by the calling thread since the program started.
std::size_t ThreadAllocationCount() noexcept;

class AllocationCounter {
 public:
  AllocationCounter() noexcept : start_(ThreadAllocationCount()) {}
  std::size_t count() const noexcept { return ThreadAllocationCount() - start_; }

 private:
  std::size_t start_;
};

}  // namespace robossis::testing
