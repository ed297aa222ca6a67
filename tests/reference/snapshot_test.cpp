// Snapshots (issue 32, docs/SNAPSHOTS.md): save_state / load_state /
// restore_state on every number type. A resumed run must give, frame for
// frame, the state hashes of the run that was never interrupted, and end with
// the same snapshot bytes (so the warm-start cache, eq 108's records, the
// sleep counters and the stage counters agree too). Bad snapshots (truncated,
// corrupt, foreign) are refused with a SnapshotError naming what is wrong.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "../../reference/src/snapshot_bytes.hpp"
#include "../../reference/src/snapshot_scene.hpp"
#include "engine_types.hpp"
#include "random_scene_gen.hpp"
#include "lockstep/builtin_scenes.hpp"
#include "lockstep/snapshot.hpp"

namespace lockstep::test {
namespace {

template <class T>
bool same(const T& a, const T& b) {
  if constexpr (std::is_same_v<T, Q16>) return a.raw() == b.raw();
  else if constexpr (std::is_same_v<T, Mp>) return a == b;
  else return std::memcmp(&a, &b, sizeof a) == 0;
}

// Every field of every body, derived ones (R, the AABB) included.
template <class T>
::testing::AssertionResult same_bodies(const World<T>& a, const World<T>& b) {
  if (a.bodies().size() != b.bodies().size()) return ::testing::AssertionFailure() << "body counts differ";
  for (std::size_t i = 0; i < a.bodies().size(); ++i) {
    const Body<T>& x = a.bodies()[i];
    const Body<T>& y = b.bodies()[i];
    bool ok = x.asleep == y.asleep && x.sleep_counter == y.sleep_counter && x.sleep_frame == y.sleep_frame &&
              x.is_static == y.is_static && same(x.inv_mass, y.inv_mass) && same(x.restitution, y.restitution) &&
              same(x.friction, y.friction) && same(x.q.w, y.q.w) && same(x.q.x, y.q.x) && same(x.q.y, y.q.y) && same(x.q.z, y.q.z);
    for (int k = 0; k < 3; ++k) {
      ok = ok && same(x.p[k], y.p[k]) && same(x.v[k], y.v[k]) && same(x.w[k], y.w[k]) && same(x.half[k], y.half[k]) &&
           same(x.inv_inertia[k], y.inv_inertia[k]) && same(x.aabb_half[k], y.aabb_half[k]);
      for (int j = 0; j < 3; ++j) ok = ok && same(x.R.row[k][j], y.R.row[k][j]);
    }
    if (!ok) return ::testing::AssertionFailure() << "body " << i << " differs";
  }
  return ::testing::AssertionSuccess();
}

// Steps `frames` frames, collecting the hash after each.
template <class T>
std::vector<std::uint64_t> hashes(World<T>& w, int frames) {
  std::vector<std::uint64_t> h;
  for (int f = 0; f < frames; ++f) {
    w.step();
    h.push_back(w.state_hash());
  }
  return h;
}

// Saves `w`, loads it (a fresh world and a restore into `other`), and checks
// that the three runs agree for `frames` frames and end with equal snapshots.
template <class T>
::testing::AssertionResult resumes(World<T> w, World<T> other, int frames) {
  const std::vector<std::uint8_t> bytes = w.save_state();
  World<T> loaded = World<T>::load_state(bytes);
  if (loaded.save_state() != bytes) return ::testing::AssertionFailure() << "load then save changed the bytes";
  if (auto r = same_bodies(w, loaded); !r) return r << " after load_state";
  other.restore_state(bytes);
  if (other.save_state() != bytes) return ::testing::AssertionFailure() << "restore then save changed the bytes";
  if (auto r = same_bodies(w, other); !r) return r << " after restore_state";
  if (loaded.frame() != w.frame() || other.frame() != w.frame()) return ::testing::AssertionFailure() << "frame differs";
  const std::vector<std::uint64_t> want = hashes(w, frames);
  const std::vector<std::uint64_t> got = hashes(loaded, frames);
  const std::vector<std::uint64_t> got2 = hashes(other, frames);
  for (int f = 0; f < frames; ++f)
    if (want[static_cast<std::size_t>(f)] != got[static_cast<std::size_t>(f)] || want[static_cast<std::size_t>(f)] != got2[static_cast<std::size_t>(f)])
      return ::testing::AssertionFailure() << "hash differs " << f + 1 << " frames after the save (frame " << w.frame() - frames + f + 1 << ")";
  if (w.save_state() != loaded.save_state() || w.save_state() != other.save_state())
    return ::testing::AssertionFailure() << "the final snapshots differ";
  return ::testing::AssertionSuccess();
}

template <class T>
class SnapshotTest : public ::testing::Test {};
using SnapshotTypes = ::testing::Types<Q16, float, double>;
TYPED_TEST_SUITE(SnapshotTest, SnapshotTypes);

// stack5 saved while falling, landing, settling and asleep (with eq 108's
// records); `other` is a world of the same scene at another frame (the
// restore's fast path) and, once, of another scene (its slow path).
TYPED_TEST(SnapshotTest, Stack5ResumesBitForBit) {
  using T = TypeParam;
  const Scene scene = *builtin_scene("stack5");
  World<T> w(scene);
  World<T> other(scene);
  for (int f = 0; f < 7; ++f) other.step();
  int at = 0;
  for (int save : {0, 1, 40, 120, 250, 400}) {
    for (; at < save; ++at) w.step();
    EXPECT_TRUE(resumes(w, other, 60)) << "saved at frame " << save;
  }
  EXPECT_TRUE(resumes(w, World<T>(*builtin_scene("bounce")), 30));
  EXPECT_TRUE(w.all_asleep()) << "stack5 should be asleep by frame 400";
}

TYPED_TEST(SnapshotTest, ScenesWithStaticsAndSdfResume) {
  using T = TypeParam;
  for (const char* name : {"bowl", "pyramid", "tip_corner", "terrain"}) {
    const Scene scene = *builtin_scene(name);
    World<T> w(scene);
    for (int f = 0; f < 90; ++f) w.step();
    EXPECT_TRUE(resumes(w, World<T>(scene), 40)) << name;
  }
}

TEST(SnapshotMp, ResumesBitForBit) {
  const Scene scene = *builtin_scene("stack5");
  World<Mp> w(scene);
  for (int f = 0; f < 25; ++f) w.step();
  EXPECT_TRUE(resumes(w, World<Mp>(scene), 4));
}

TEST(SnapshotMp, ValuesRoundTripExactly) {
  Scene scene = *builtin_scene("drop");
  scene.bodies[0].velocity = {1.0 / 3.0, -0.0, 1e-30};
  World<Mp> w(scene);
  w.step();
  const World<Mp> loaded = World<Mp>::load_state(w.save_state());
  EXPECT_TRUE(same_bodies(w, loaded));
}

// The loaded world's scene is the snapshot's, its bodies at the saved state.
TEST(Snapshot, LoadedSceneHoldsTheSavedState) {
  World<Q16> w(*builtin_scene("stack5"));
  for (int f = 0; f < 30; ++f) w.step();
  const World<Q16> loaded = World<Q16>::load_state(w.save_state());
  EXPECT_EQ(loaded.scene().name, "stack5");
  EXPECT_EQ(loaded.scene().bodies.size(), w.bodies().size());
  EXPECT_EQ(loaded.scene().bodies[2].position.y, d(w.body(2).p.y));
  EXPECT_EQ(loaded.constants_hash(), w.constants_hash());
  const SnapshotInfo info = [&] {
    const auto b = w.save_state();
    return read_snapshot_info(b.data(), b.size());
  }();
  EXPECT_EQ(info.frame, 30u);
  EXPECT_EQ(info.body_count, 5u);
  EXPECT_EQ(info.number, SnapshotNumber::kFixed);
}

// ---- Random scenes, random save frames ------------------------------------

template <class T>
void random_resume_property(int max_frames) {
  const Scene scene = *random_scene();
  const int frames = *rc::gen::inRange(1, max_frames + 1);
  const int save = *rc::gen::inRange(0, frames + 1);
  const int other_frames = *rc::gen::inRange(0, 20);
  World<T> w(scene);
  World<T> other(scene);
  try {
    for (int f = 0; f < save; ++f) w.step();
    for (int f = 0; f < other_frames; ++f) other.step();
    const auto r = resumes(w, other, frames - save);
    RC_ASSERT(static_cast<bool>(r));
  } catch (const RunError&) {
    RC_DISCARD("the run stopped (RunError)");
  }
}

RC_GTEST_PROP(SnapshotProperty, RandomScenesResumeFixed, ()) { random_resume_property<Q16>(300); }
RC_GTEST_PROP(SnapshotProperty, RandomScenesResumeFloat, ()) { random_resume_property<float>(300); }
RC_GTEST_PROP(SnapshotProperty, RandomScenesResumeDouble, ()) { random_resume_property<double>(300); }

// ---- Refusals ----------------------------------------------------------------

// A snapshot changed after its checksum: the checksum is recomputed, so the
// change reaches the checks behind it.
void reseal(std::vector<std::uint8_t>& b) {
  const std::uint64_t sum = snap::checksum(b.data(), b.size() - 8);
  for (int i = 0; i < 8; ++i) b[b.size() - 8 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(sum >> (8 * i));
}

template <class T>
std::string refusal(const std::vector<std::uint8_t>& b) {
  try {
    (void)World<T>::load_state(b);
  } catch (const SnapshotError& e) {
    return e.what();
  }
  return "";
}

std::vector<std::uint8_t> settled_stack() {
  World<Q16> w(*builtin_scene("stack5"));
  for (int f = 0; f < 300; ++f) w.step();
  return w.save_state();
}

TEST(SnapshotRefusal, EveryTruncationIsRefused) {
  const std::vector<std::uint8_t> good = settled_stack();
  for (std::size_t n = 0; n < good.size(); ++n) {
    const std::vector<std::uint8_t> cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n));
    const std::string why = refusal<Q16>(cut);
    ASSERT_NE(why, "") << n << " bytes loaded";
    ASSERT_NE(why.find("truncated"), std::string::npos) << n << " bytes: " << why;
  }
}

TEST(SnapshotRefusal, EveryBitFlipIsRefused) {
  const std::vector<std::uint8_t> good = settled_stack();
  for (std::size_t i = 0; i < good.size(); ++i) {
    std::vector<std::uint8_t> bad = good;
    bad[i] ^= static_cast<std::uint8_t>(1u << (i % 8));
    ASSERT_NE(refusal<Q16>(bad), "") << "a flip of byte " << i << " loaded";
  }
  std::vector<std::uint8_t> bad = good;
  bad[bad.size() / 2] ^= 0x10;
  EXPECT_NE(refusal<Q16>(bad).find("checksum"), std::string::npos) << refusal<Q16>(bad);
}

TEST(SnapshotRefusal, ForeignSnapshotsNameWhatIsWrong) {
  std::vector<std::uint8_t> good = settled_stack();
  const std::string foreign = refusal<float>(good);
  EXPECT_NE(foreign.find("fixed"), std::string::npos) << foreign;
  EXPECT_NE(foreign.find("float"), std::string::npos) << foreign;
  World<double> dw(*builtin_scene("stack5"));
  EXPECT_THROW(dw.restore_state(good), SnapshotError);

  std::vector<std::uint8_t> v3 = good;  // a later format (this build reads version 2)
  v3[8] = 3;
  reseal(v3);
  EXPECT_NE(refusal<Q16>(v3).find("format version 3"), std::string::npos) << refusal<Q16>(v3);
  std::vector<std::uint8_t> v1 = good;  // version 1 had no id table and no pending forces
  v1[8] = 1;
  reseal(v1);
  EXPECT_NE(refusal<Q16>(v1).find("format version 1"), std::string::npos) << refusal<Q16>(v1);

  std::vector<std::uint8_t> magic = good;
  magic[0] = '{';
  EXPECT_NE(refusal<Q16>(magic).find("not a lockstep snapshot"), std::string::npos);

  std::vector<std::uint8_t> longer = good;
  longer.push_back(0);
  EXPECT_NE(refusal<Q16>(longer).find("after the end"), std::string::npos) << refusal<Q16>(longer);

  EXPECT_NE(refusal<Q16>({}).find("truncated"), std::string::npos);
}

TEST(SnapshotRefusal, CorruptFieldsBehindAGoodChecksum) {
  const std::vector<std::uint8_t> good = settled_stack();
  const Scene scene = *builtin_scene("stack5");
  const std::size_t body0 = kSnapshotHeaderSize + snap::encode_scene_section(scene).size();

  std::vector<std::uint8_t> hash = good;
  hash[16] ^= 1;  // the constants hash
  reseal(hash);
  EXPECT_NE(refusal<Q16>(hash).find("constants hash"), std::string::npos) << refusal<Q16>(hash);

  std::vector<std::uint8_t> count = good;
  count[12] = 6;  // body count 6 for 5 bodies
  reseal(count);
  EXPECT_NE(refusal<Q16>(count), "");

  std::vector<std::uint8_t> q = good;  // body 0's orientation (after flags and p) all zero
  std::memset(q.data() + body0 + 1 + 12, 0, 16);
  reseal(q);
  EXPECT_NE(refusal<Q16>(q).find("body 0: q"), std::string::npos) << refusal<Q16>(q);

  std::vector<std::uint8_t> flags = good;
  flags[body0] |= 0x80;
  reseal(flags);
  EXPECT_NE(refusal<Q16>(flags).find("reserved bits"), std::string::npos) << refusal<Q16>(flags);

  // A double snapshot with a NaN position.
  World<double> dw(scene);
  dw.step();
  std::vector<std::uint8_t> nan = dw.save_state();
  const double q_nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(nan.data() + body0 + 1, &q_nan, sizeof q_nan);
  reseal(nan);
  EXPECT_NE(refusal<double>(nan).find("body 0: p"), std::string::npos) << refusal<double>(nan);
}

// The format's byte layout as documented (docs/SNAPSHOTS.md): header fields at
// their offsets.
TEST(Snapshot, HeaderLayout) {
  World<Q16> w(*builtin_scene("stack5"));
  for (int f = 0; f < 3; ++f) w.step();
  const std::vector<std::uint8_t> b = w.save_state();
  EXPECT_EQ(std::string(b.begin(), b.begin() + 8), "LKSTSNAP");
  EXPECT_EQ(b[8] | b[9] << 8, 2);
  EXPECT_EQ(b[10], 1);
  EXPECT_EQ(b[12], 5);
  std::uint64_t hash = 0, size = 0;
  for (int i = 0; i < 8; ++i) hash |= static_cast<std::uint64_t>(b[16 + static_cast<std::size_t>(i)]) << (8 * i);
  for (int i = 0; i < 8; ++i) size |= static_cast<std::uint64_t>(b[24 + static_cast<std::size_t>(i)]) << (8 * i);
  EXPECT_EQ(hash, w.constants_hash());
  EXPECT_EQ(size, b.size());
  EXPECT_EQ(b[32], 3);
}

}  // namespace
}  // namespace lockstep::test

namespace lockstep::test {
namespace {

std::size_t varint_at(const std::vector<std::uint8_t>& b, std::size_t& at) {
  const std::size_t from = at;
  while (b.at(at) & 0x80) ++at;
  ++at;
  return at - from;
}

// issue 32's budget, on the fixed engine's settled pile1000: the moving state
// (flags, pose, velocities, sleep counter and frame) at most 64 B per body,
// the whole snapshot at most 128 B per body. Prints the breakdown that
// docs/SNAPSHOTS.md reports.
TEST(SnapshotSize, SettledPile1000WithinBudget) {
  const Scene scene = *builtin_scene("pile1000");
  World<Q16> w(scene);
  for (int f = 0; f < 600; ++f) w.step();
  ASSERT_TRUE(w.all_asleep());
  const std::vector<std::uint8_t> b = w.save_state();
  const std::size_t section = snap::encode_scene_section(scene).size();
  std::size_t at = kSnapshotHeaderSize + section, moving = 0, records = 0, record_bytes = 0;
  for (std::size_t i = 0; i < w.bodies().size(); ++i) {
    const std::size_t from = at;
    const std::uint8_t flags = b.at(at);
    at += 1 + 28 + ((flags & 2) ? 12 : 0) + ((flags & 4) ? 12 : 0);
    varint_at(b, at);
    if (flags & 8) varint_at(b, at);
    moving += at - from;
    const std::size_t rests_from = at;
    for (int r = 0; r < (flags >> 4); ++r) {
      const std::size_t key_at = at;
      varint_at(b, at);
      at += 24 + ((b.at(key_at) & 1) ? 12 : 0);
      ++records;
    }
    record_bytes += at - rests_from;
  }
  const std::size_t warm_and_counters = b.size() - kSnapshotChecksumSize - at;  // with the id table and pending forces (2 bytes)
  const double n = static_cast<double>(w.bodies().size());
  std::printf("pile1000 (fixed, frame %d, all asleep): %zu bytes = %.1f B/body: header %zu, scene section %zu, "
              "moving state %zu (%.1f B/body), eq 108 records %zu in %zu bytes (%.1f B/body), warm cache, ids, forces and counters %zu, "
              "checksum %zu\n",
              w.frame(), b.size(), static_cast<double>(b.size()) / n, kSnapshotHeaderSize, section, moving,
              static_cast<double>(moving) / n, records, record_bytes, static_cast<double>(record_bytes) / n,
              warm_and_counters, kSnapshotChecksumSize);
  EXPECT_LE(static_cast<double>(moving) / n, 64.0);
  EXPECT_LE(static_cast<double>(b.size()) / n, 128.0);
  // Awake: the same pile at frame 60, still falling (velocities and the warm-start cache).
  World<Q16> falling(scene);
  for (int f = 0; f < 60; ++f) falling.step();
  const std::size_t awake_bytes = falling.save_state().size();
  std::printf("pile1000 (fixed, frame 60, %d awake): %zu bytes = %.1f B/body\n", falling.awake_count(), awake_bytes,
              static_cast<double>(awake_bytes) / n);
  EXPECT_LE(static_cast<double>(awake_bytes) / n, 128.0);
}

}  // namespace
}  // namespace lockstep::test
