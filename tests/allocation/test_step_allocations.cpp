// The step allocates no memory after warm-up (issue 7): heap allocation in the hot loop
// makes frame times jitter and threads contend for the allocator. Every buffer of a step
// is kept across steps (State::scratch, the row builders' buffers among it, the
// Delassus and column caches' growable storage) and CHOLMOD's memory goes through a pool
// (engine/solve/cholmod_memory_pool.hpp). Storage still grows when a size exceeds every
// earlier step's (more contact rows than ever before): the windows below are steps where
// the scenes' sizes stay within what their warm-up saw.
//
// Its own program: it replaces malloc and friends with counting wrappers over glibc's, so
// that Eigen's, the standard library's and Embree's allocations count. TBB's own allocator
// (libtbbmalloc, through mmap) is not seen: TBB's internal structures are not counted. Not in
// the sanitizer build (ASan owns malloc there). Known exception, counted apart: GNU
// OpenMP's teams inside CHOLMOD's supernodal factorisation (note() below).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <dlfcn.h>

#include <atomic>
#include <cstring>
#include <cstdlib>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <thread>

#include "engine/constraints/contact_rows.hpp"
#include "engine/constraints/energy_limit.hpp"
#include "engine/constraints/strain_limit_rows.hpp"
#include "engine/scene/scene.hpp"
#include "engine/world.hpp"

extern "C" void* __libc_malloc(size_t);
extern "C" void* __libc_calloc(size_t, size_t);
extern "C" void* __libc_realloc(void*, size_t);
extern "C" void* __libc_memalign(size_t, size_t);

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0}, g_openmp_allocations{0};
thread_local bool t_noting = false;

// Counts an allocation called from `caller`. CHOLMOD's supernodal factorisation (systems
// above LinearSolver::kSupernodalThreshold DOFs) runs OpenMP loops, and GNU OpenMP
// allocates a team for every parallel region that runs on one thread: those are counted
// apart (reported, not asserted; nothing sinew can reuse).
void note(void* caller) {
  if (!g_counting.load(std::memory_order_relaxed) || t_noting) return;
  t_noting = true;
  Dl_info info;
  const bool openmp = dladdr(caller, &info) && info.dli_fname && std::strstr(info.dli_fname, "libgomp");
  (openmp ? g_openmp_allocations : g_allocations).fetch_add(1, std::memory_order_relaxed);
  t_noting = false;
}
}  // namespace

extern "C" void* malloc(size_t n) {
  note(__builtin_return_address(0));
  return __libc_malloc(n);
}
extern "C" void* calloc(size_t a, size_t b) {
  note(__builtin_return_address(0));
  return __libc_calloc(a, b);
}
extern "C" void* realloc(void* p, size_t n) {
  note(__builtin_return_address(0));
  return __libc_realloc(p, n);
}
extern "C" int posix_memalign(void** p, size_t alignment, size_t n) {
  note(__builtin_return_address(0));
  *p = __libc_memalign(alignment, n);
  return *p ? 0 : 12;  // ENOMEM
}
extern "C" void* aligned_alloc(size_t alignment, size_t n) {
  note(__builtin_return_address(0));
  return __libc_memalign(alignment, n);
}
extern "C" void* memalign(size_t alignment, size_t n) {
  note(__builtin_return_address(0));
  return __libc_memalign(alignment, n);
}

namespace {

// Allocations made by `work` on any thread, outside OpenMP's runtime and inside it.
struct Count {
  long ours = 0, openmp = 0;
};
template <typename Work>
Count allocations_during(Work&& work) {
  const long before = g_allocations.load(), openmp_before = g_openmp_allocations.load();
  g_counting = true;
  work();
  g_counting = false;
  return {g_allocations.load() - before, g_openmp_allocations.load() - openmp_before};
}

struct Window {
  const char* scene;  // in assets/scenes
  int warmup, steps;
  bool one_thread_too;  // also run on 1 thread (the cheap scenes; TBB's path is the same code)
};

}  // namespace

TEST_CASE("allocation counter: it sees malloc, new and Eigen") {
  // Without this the test below could pass with a counter that never counts.
  CHECK(allocations_during([] { std::free(std::malloc(64)); }).ours == 1);
  CHECK(allocations_during([] { delete new std::vector<int>(100); }).ours == 2);
  CHECK(allocations_during([] { sinew::VecX v(1000); v.setZero(); }).ours == 1);
}

TEST_CASE("a warm step allocates nothing, on 2 threads and on 1") {
  // Every kind of step: energy limits with contact (creature, sphere), energy limits alone
  // (beam), strain limits with a kinematic press (finger) and alone (beam), collapse, two
  // bodies in contact (the default demo), Newton on Stable Neo-Hookean, alone and with contact
  // (the Newton predictor, CG preconditioned by an older factor), a box at rest on a plane
  // (the SQP's KKT stop). Warm-ups long
  // enough for each scene's rows to reach the sizes of the window.
  const Window windows[] = {{"default", 40, 20, false},
                            {"paper000_beam_150kPa_U0.5", 60, 30, true},
                            {"paper000_sphere_150kPa_U500", 60, 30, true},
                            {"paper000_collapse_50kPa_U50", 60, 20, true},
                            {"paper000_creature_500kPa_U100", 120, 30, true},
                            {"paper001_finger_flat_anisotropic", 90, 20, false},
                            {"paper001_beam_5kPa_isotropic", 60, 20, true},
                            {"paper003_elbow_snh", 60, 20, false},
                            {"contact_snh_box_on_plane", 60, 30, true},
                            {"contact_box_on_plane", 100, 30, true}};
  for (const int threads : {2, 1}) {
    tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
    for (const Window& w : windows) {
      if (threads == 1 && !w.one_thread_too) continue;
      const std::string name = w.scene;
      CAPTURE(threads);
      CAPTURE(name);
      sinew::SceneDesc scene = sinew::load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/" + name + ".json");
      // Awake steps only, as the benchmarks time them: a scene that comes to rest inside its
      // window (the strain-limited beam and finger do, once PGS's subspace steps solve
      // their LCPs to tolerance) would otherwise time a sleeping step's first entry.
      scene.solver.sleep_steps = 0;
      sinew::World world(sinew::build_model(scene, [](const std::string&) {}), sinew::initial_velocities(scene));
      for (int i = 0; i < w.warmup; ++i) REQUIRE(world.step());
      bool ok = true;
      const Count count = allocations_during([&] {
        for (int i = 0; i < w.steps && ok; ++i) ok = world.step();
      });
      REQUIRE(ok);
      MESSAGE(name << ", " << threads << " thread(s): " << count.ours << " allocations in " << w.steps
                   << " steps after " << w.warmup << " (and " << count.openmp << " by OpenMP in CHOLMOD)");
      CHECK(count.ours == 0);
      // The box at rest: its steps take the Newton predictor's path (the window covers it).
      if (name == "contact_snh_box_on_plane") CHECK(world.profile().iterations.at("newton_predicted") == 1);
      // The box at rest: its steps end by the SQP's KKT stop (the window covers that path).
      if (name == "contact_box_on_plane") CHECK(world.profile().iterations.at("sqp_kkt_stops") == 1);
    }
  }
}

TEST_CASE("a warm Newton step with strain limits and contact allocates nothing (QPs on H plus curvature)") {
  // Paper 001's side-pressed finger in Stable Neo-Hookean: Newton ends by factorising H plus
  // the last step's strain-row curvature (solve_newton.cpp), then the SQP with contact.
  for (const int threads : {2, 1}) {
    tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
    CAPTURE(threads);
    sinew::SceneDesc scene =
        sinew::load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper001_finger_side_anisotropic.json");
    scene.bodies[0].material.model = "stable_neo_hookean";
    scene.bodies[0].damping_mass = 2;
    scene.bodies[0].damping_stiffness = 0;
    scene.solver.sleep_steps = 0;
    sinew::World world(sinew::build_model(scene, [](const std::string&) {}), sinew::initial_velocities(scene));
    for (int i = 0; i < 60; ++i) REQUIRE(world.step());  // the press ramps in over 30 steps
    bool ok = true;
    long curved = 0;
    const Count count = allocations_during([&] {
      for (int i = 0; i < 20 && ok; ++i) {
        ok = world.step();
        curved += world.profile().iterations.at("newton_curved_factorisations");
      }
    });
    REQUIRE(ok);
    MESSAGE(threads << " thread(s): " << count.ours << " allocations in 20 steps after 60 (and " << count.openmp
                    << " by OpenMP in CHOLMOD); curved factorisations " << curved);
    CHECK(curved > 0);  // the path under test ran
    CHECK(count.ours == 0);
  }
}

TEST_CASE("a warm PCG step allocates nothing (solver.linear \"pcg\", contact columns by CG)") {
  for (const int threads : {2, 1}) {
    tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
    CAPTURE(threads);
    sinew::SceneDesc scene = sinew::load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/contact_box_on_plane.json");
    scene.solver.linear = "pcg";
    scene.solver.sleep_steps = 0;
    sinew::World world(sinew::build_model(scene, [](const std::string&) {}), sinew::initial_velocities(scene));
    for (int i = 0; i < 60; ++i) REQUIRE(world.step());
    bool ok = true;
    const Count count = allocations_during([&] {
      for (int i = 0; i < 20 && ok; ++i) ok = world.step();
    });
    REQUIRE(ok);
    REQUIRE(world.profile().iterations.at("pcg_solves") > 1);  // the contact rows' columns too
    MESSAGE("contact_box_on_plane (pcg), " << threads << " thread(s): " << count.ours << " allocations in 20 steps");
    CHECK(count.ours == 0);
  }
}

TEST_CASE("row builders given the step's buffers allocate nothing on a thread that never ran them") {
  // build_rows runs the limits and the contacts as two tasks on whichever thread is free.
  // With buffers kept per thread, a worker running a builder for the first time after
  // warm-up allocated them (the flat finger, 7 of 36 runs of the test above under load).
  // Here a fresh thread runs the builders with the step's own buffers (StepScratch), once
  // oneTBB knows the thread (its registration allocates, and is not what is tested).
  sinew::SceneDesc scene =
      sinew::load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper001_finger_flat_anisotropic.json");
  scene.solver.sleep_steps = 0;
  sinew::World world(sinew::build_model(scene, [](const std::string&) {}), sinew::initial_velocities(scene));
  for (int i = 0; i < 90; ++i) REQUIRE(world.step());
  sinew::State& s = world.mutable_state();
  const sinew::Model& model = world.model();
  std::vector<uint64_t> keep;
  for (const auto& [key, lambda] : s.warm_start)
    if (lambda > 0) keep.push_back(key);
  std::sort(keep.begin(), keep.end());
  sinew::RowTable limits, contacts;
  sinew::StepScratch& sc = s.scratch;
  const auto build = [&] {
    limits.clear();
    contacts.clear();
    sinew::add_energy_limit_rows(model, s.x, model.solver.activation_margin, keep, limits, &s.energy_screen,
                                 &sc.energy_row_buffers);
    sinew::add_strain_limit_rows(model, s.x, model.solver.strain_activation_margin, keep, limits,
                                 &sc.strain_row_buffers);
    sinew::add_contact_rows(model, s.t + model.h, s.x, s.v, keep, contacts, sinew::ContactSearch::BroadPhase,
                            &sc.contact_row_buffers);
  };
  // The same builders without buffers of their own keep them per thread: the fresh thread
  // then allocates, which this test must be able to see.
  const auto build_per_thread = [&] {
    limits.clear();
    contacts.clear();
    sinew::add_energy_limit_rows(model, s.x, model.solver.activation_margin, keep, limits, &s.energy_screen);
    sinew::add_strain_limit_rows(model, s.x, model.solver.strain_activation_margin, keep, limits);
    sinew::add_contact_rows(model, s.t + model.h, s.x, s.v, keep, contacts);
  };
  build();  // the tables and buffers sized on this thread
  build_per_thread();
  REQUIRE(limits.size() > 40);
  REQUIRE(contacts.size() > 0);
  Count own, per_thread;
  std::thread fresh([&] {
    tbb::parallel_for(0, 64, [](int) {});  // oneTBB registers this thread
    own = allocations_during(build);
    per_thread = allocations_during(build_per_thread);
  });
  fresh.join();
  MESSAGE("builders on a fresh thread: " << limits.size() << " limit rows, " << contacts.size() << " contact rows; "
                                         << own.ours << " allocations with the step's buffers, " << per_thread.ours
                                         << " with per-thread ones");
  CHECK(own.ours == 0);
  CHECK(per_thread.ours > 0);
}
