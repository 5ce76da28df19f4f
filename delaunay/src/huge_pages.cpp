// advise_huge_pages (declared in voroclip/delaunay.h).
#include <cstdint>

#include "voroclip/delaunay.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace voroclip::detail {

namespace {
thread_local bool t_advice_enabled = true;
}  // namespace

HugePageAdvice::HugePageAdvice(bool enabled) noexcept : previous_(t_advice_enabled) {
  t_advice_enabled = enabled;
}

HugePageAdvice::~HugePageAdvice() { t_advice_enabled = previous_; }

void advise_huge_pages(void* p, std::size_t bytes) noexcept {
  if (!t_advice_enabled) return;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // Only whole huge pages: the advice on a partial one would split the mapping for nothing.
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  const auto begin = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHuge - 1);
  // A failure (THP disabled, memory not from mmap) leaves ordinary pages: nothing to do.
  if (first < last)
    static_cast<void>(madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE));
#else
  static_cast<void>(p);
  static_cast<void>(bytes);
#endif
}

}  // namespace voroclip::detail
