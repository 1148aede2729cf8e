// The fly program's global operator new: blocks of 2 MiB and more are 2 MiB-aligned and advised as
// transparent huge pages (madvise MADV_HUGEPAGE), so that the kernel maps them 2 MiB at a time instead of
// faulting in 4 KiB pages one by one.
//
// Why: a scene's arrays (the glTF buffer, the SDB meshes, the TraceRdb, the sensors' and the baker's tables)
// are large blocks written once, right after they are allocated. Every first write to a 4 KiB page is a page
// fault, which costs about a microsecond on bare metal and tens of microseconds in some virtual machines:
// there a 65 536-triangle model's ~30 MB of fresh arrays cost more in page faults than in their computation
// (docs/benchmarks.md, "Start-up of small scenes"). A 2 MiB page takes one fault. Smaller blocks keep
// malloc's packing. The memory is malloc's (aligned_alloc), so the standard operator delete (free) releases
// it; where the kernel has no transparent huge pages, the advice is ignored and nothing else changes.
#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

namespace {

constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;  // x86-64's PMD page

void* allocate(std::size_t bytes) {
  if (bytes < kHugePageBytes) return std::malloc(bytes == 0 ? 1 : bytes);
  if (bytes > SIZE_MAX - kHugePageBytes) return nullptr;
  const std::size_t rounded = (bytes + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
  void* block = std::aligned_alloc(kHugePageBytes, rounded);
  if (block != nullptr) madvise(block, rounded, MADV_HUGEPAGE);  // advice: failure changes nothing
  return block;
}

}  // namespace

// [new.delete.single]: loops over the new-handler until allocation succeeds, else throws std::bad_alloc. The
// array and nothrow forms of the standard library call this one.
void* operator new(std::size_t bytes) {
  for (;;) {
    if (void* block = allocate(bytes)) return block;
    const std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
  }
}
