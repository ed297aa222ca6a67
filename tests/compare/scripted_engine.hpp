// A synthetic engine for harness tests: every body's state at every frame is
// given by a function, so a test controls exactly where engines differ.
#pragma once
#include <functional>
#include <string>
#include <utility>

#include "lockstep/compare/engine.hpp"

namespace lockstep_test {

using lockstep::BodySnapshot;

// state(frame, body) -> the body's snapshot at that frame.
using Script = std::function<BodySnapshot(int frame, int body)>;

class ScriptedEngine final : public lockstep::EngineRun {
 public:
  ScriptedEngine(std::string name, int bodies, Script script, int fail_frame = -1, int fail_body = -1)
      : name_(std::move(name)), bodies_(bodies), script_(std::move(script)), fail_frame_(fail_frame), fail_body_(fail_body) {}
  std::string name() const override { return name_; }
  std::string description() const override { return name_ + ": scripted"; }
  void step() override {
    if (frame_ + 1 == fail_frame_) throw lockstep::RunError(fail_frame_, fail_body_, "velocity", "scripted overflow");
    ++frame_;
  }
  int frame() const override { return frame_; }
  int body_count() const override { return bodies_; }
  BodySnapshot body(int i) const override { return script_(frame_, i); }
  std::uint64_t state_hash() const override { return static_cast<std::uint64_t>(frame_); }
  double energy() const override {
    double e = 0;
    for (int i = 0; i < bodies_; ++i) e += 9.81 * script_(frame_, i).p[1];
    return e;
  }
  lockstep::StageCounters counters() const override { return {}; }

 private:
  std::string name_;
  int bodies_;
  Script script_;
  int fail_frame_, fail_body_;
  int frame_ = 0;
};

// A snapshot at rest: position p, identity orientation (+y up), asleep from
// sleep_frame on (never if < 0) as seen at `frame`.
inline BodySnapshot at(double x, double y, double z, int frame = 0, int sleep_frame = -1) {
  BodySnapshot b{};
  b.p[0] = x; b.p[1] = y; b.p[2] = z;
  b.q[0] = 1;
  b.asleep = sleep_frame >= 0 && frame >= sleep_frame;
  b.sleep_frame = b.asleep ? sleep_frame : -1;
  return b;
}

}  // namespace lockstep_test
