// accumulation.h — what the window's image holds and what a change does to
// it: bookkeeping without a window, unit-tested (tests/test_view.cpp).
#pragma once

#include <algorithm>
#include <cstdint>

#include "render/render_control.h"

namespace wp {

class ViewAccumulation {
 public:
  // `stratified`: the sampler's strata depend on the sample count (CMJ).
  ViewAccumulation(uint32_t target, bool stratified) : target_(std::max(target, 1u)), stratified_(stratified) {}

  uint32_t target() const { return target_; }
  uint32_t reached() const { return reached_; }
  bool done() const { return reached_ >= target_; }
  // The samples still to render, every pixel.
  SampleRange todo() const { return {reached_, target_}; }
  void reach(uint32_t sample) { reached_ = std::min(sample, target_); }

  // The view, the lens, the bounces or the kernels changed: from sample 0.
  void restart() { reached_ = 0; }
  void set_stratified(bool stratified) { stratified_ = stratified; }

  // ] and [: more samples continue the image; fewer than it holds start it
  // again, as does any new count under stratified sampling. Returns whether
  // the image starts again.
  bool set_target(uint32_t target) {
    target = std::max(target, 1u);
    const bool again = target != target_ && (stratified_ || reached_ > target);
    target_ = target;
    if (again) restart();
    return again;
  }

 private:
  uint32_t target_;
  uint32_t reached_ = 0;
  bool stratified_;
};

}  // namespace wp
