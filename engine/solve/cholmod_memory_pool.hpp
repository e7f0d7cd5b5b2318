#pragma once
// CHOLMOD's memory through a pool that keeps freed blocks for reuse. A numeric
// factorisation allocates and frees the same blocks every time (permuted copies of A, the
// factor's workspace): with the pool, a step that refactorises allocates nothing from the
// system once the pool holds one block of each size (the step is allocation-free after
// warm-up, issue 7). Blocks come in power-of-two sizes up to 64 MiB; larger ones are
// allocated at their size and freed at once. Installed before main: every block CHOLMOD
// frees must come from the pool.
namespace sinew {

// Routes SuiteSparse's allocator (SuiteSparse_config) through the pool; idempotent, thread
// safe. Call before the first CHOLMOD call that allocates (LinearSolver does).
void install_cholmod_memory_pool();

// Blocks the pool holds for reuse, and bytes in them (tests, diagnostics).
struct CholmodPoolStats {
  long free_blocks = 0;
  long free_bytes = 0;
};
CholmodPoolStats cholmod_memory_pool_stats();

}  // namespace sinew
