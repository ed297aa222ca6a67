// EngineRun::apply (issue 32): every engine of engine_names() takes the
// run-time inputs through the type-erased interface that record and replay
// drive, with the same ids, body counts and refusals, and the CPU engines
// give World<T>'s bits for them.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/engine.hpp"
#include "lockstep/fixed/q16_vec.hpp"

namespace lockstep {
namespace {

std::vector<Input> some_inputs() {
  std::vector<Input> out;
  Input crate;
  crate.frame = 3;
  crate.kind = InputKind::create;
  crate.body.half_extents = {0.75, 0.5, 0.25};
  crate.body.position = {2.0, 4.0, 0.0};
  out.push_back(crate);
  Input gone;
  gone.frame = 5;
  gone.kind = InputKind::destroy;
  gone.id = {2, 0};
  out.push_back(gone);
  Input kick;
  kick.frame = 5;
  kick.kind = InputKind::impulse;
  kick.id = {5, 0};  // the crate
  kick.a = {0.0, 3.0, 1.0};
  kick.b = {2.5, 4.0, 0.0};
  out.push_back(kick);
  Input push;
  push.frame = 9;
  push.kind = InputKind::force;
  push.id = {4, 0};
  push.a = {20.0, 0.0, 0.0};
  push.b = {0.0, 1.0, 0.0};
  out.push_back(push);
  return out;
}

TEST(EngineInputs, EveryEngineTakesTheInputs) {
  const Scene scene = *builtin_scene("stack5");
  set_quiet_engines(true);
  for (const std::string& name : engine_names()) {
    SCOPED_TRACE(name);
    std::unique_ptr<EngineRun> e = make_engine(name, scene);
    std::size_t k = 0;
    const std::vector<Input> inputs = some_inputs();
    for (int f = 1; f <= 20; ++f) {
      for (; k < inputs.size() && inputs[k].frame == f; ++k) e->apply(inputs[k]);
      e->step();
    }
    EXPECT_EQ(e->body_count(), 5);
    Input stale;
    stale.frame = e->frame() + 1;
    stale.kind = InputKind::wake;
    stale.id = {2, 0};
    try {
      e->apply(stale);
      ADD_FAILURE() << "a stale id was taken";
    } catch (const std::invalid_argument& err) {
      EXPECT_NE(std::string(err.what()).find("stale"), std::string::npos) << err.what();
    }
  }
}

// The fixed engine behind EngineRun gives World<Q16>'s bits with the inputs.
TEST(EngineInputs, FixedThroughEngineRunIsWorldQ16) {
  const Scene scene = *builtin_scene("stack5");
  std::unique_ptr<EngineRun> e = make_engine("fixed", scene);
  World<Q16> w(scene);
  std::size_t k = 0;
  const std::vector<Input> inputs = some_inputs();
  for (int f = 1; f <= 60; ++f) {
    for (; k < inputs.size() && inputs[k].frame == f; ++k) {
      e->apply(inputs[k]);
      w.apply(inputs[k]);
    }
    e->step();
    w.step();
    ASSERT_EQ(e->state_hash(), w.state_hash()) << "frame " << f;
  }
}

}  // namespace
}  // namespace lockstep
