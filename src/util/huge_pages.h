// huge_pages.h — large arrays backed by transparent huge pages. Filling fresh
// memory faults once per 4 KiB page; on the benchmark VM a fault costs about
// 10 us, so writing a new 35 MiB node array took 90 ms on 4 KiB pages and 7 ms
// on 2 MiB ones. The builder's, the collapse's and the scene compiler's big
// arrays are allocated through these, and lavapipe's buffers are advised
// (vulkan_context.cpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <vector>

namespace wp {

// Asks Linux to back the whole 2 MiB pages inside [p, p + bytes) with huge
// pages when they are first touched. Only a hint: a no-op elsewhere, and for
// ranges too small to hold a whole huge page.
void advise_huge_pages(void* p, size_t bytes);

// Reserves room for n elements in v and advises huge pages for it. Call it
// on a vector without room yet, so that the room is new and untouched.
template <typename T>
void reserve_huge(std::vector<T>& v, size_t n) {
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

// An uninitialized array of trivial elements on huge pages: a working set
// that is written before it is read (the BVH builder's references and nodes,
// the collapse's subtree sizes).
template <typename T>
class WorkArray {
  static_assert(std::is_trivially_destructible_v<T>);

 public:
  explicit WorkArray(size_t n) {
    constexpr size_t kHuge = size_t(2) << 20;
    size_t bytes = std::max<size_t>(1, n) * sizeof(T);
    // Arrays under a huge page stay on small pages: a fresh huge page is
    // zeroed whole (2 MiB) however little of it is used.
    const size_t align = bytes < kHuge ? std::max(alignof(std::max_align_t), alignof(T)) : kHuge;
    bytes = (bytes + align - 1) / align * align;  // aligned_alloc wants a multiple of the alignment
    data_ = static_cast<T*>(std::aligned_alloc(align, bytes));
    if (!data_) throw std::bad_alloc();
    if (align == kHuge) advise_huge_pages(data_, bytes);
  }
  ~WorkArray() { std::free(data_); }
  WorkArray(const WorkArray&) = delete;
  WorkArray& operator=(const WorkArray&) = delete;
  T* get() const { return data_; }
  T& operator[](size_t i) const { return data_[i]; }
  // Frees the array before the owner goes (get() is then null).
  void release() {
    std::free(data_);
    data_ = nullptr;
  }

 private:
  T* data_ = nullptr;
};

}  // namespace wp
