#include "meshmark/huge_pages.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace meshmark {

void advise_huge_pages(void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::size_t kMin = std::size_t(4) << 20, kPage = 4096;
  if (p == nullptr || bytes < kMin) return;
  const std::uintptr_t a = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = (a + kPage - 1) & ~std::uintptr_t(kPage - 1);  // madvise needs page alignment
  if (first - a >= bytes) return;
  madvise(reinterpret_cast<void*>(first), bytes - (first - a), MADV_HUGEPAGE);  // a hint: failure is harmless
#else
  (void)p;
  (void)bytes;
#endif
}

}  // namespace meshmark
