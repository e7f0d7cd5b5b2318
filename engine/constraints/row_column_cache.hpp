#pragma once
// Columns y_i = H^-1 J_i^T of constraint rows, kept for the life of one factorisation of the
// step's system matrix H: a row whose stencil (nodes and Jacobian, bit for bit) is the one
// its column was solved for is not solved again. For the Delassus matrix formed from one
// solve per row (delassus.hpp, build_direct): contacts on a plane or a kinematic plate keep
// their Jacobian across SQP iterations (the embedded weights and the normal do not move),
// so only the rows that changed, mostly energy limits, cost solves after the first iteration.
// Optionally (`node_budget` > 0), energy-limit rows, whose Jacobian moves at every iteration
// while their 8 nodes stay, take y_i from node columns instead: H^-1 on the 3 DOFs of each
// of their nodes, solved with the first call after a factorisation for the nodes of the
// energy rows present then, and combined as y_i = sum over the row's nodes n of
// (H^-1 E_n) J_in^T (E_n: the node's 3 DOFs; 3 n multiply-adds per node, no solve).
// Worth it when the factorisation serves several steps (refactor_interval > 1): the
// solves then happen once, in one large batch, in the step that factorises. Taken only
// when the node columns number at most `node_budget` per energy row and hold at most
// kNodeColumnEntries values; else the energy rows are solved per row like the others.
#include <algorithm>
#include <cstdint>
#include <deque>
#include <limits>
#include <vector>

#include "engine/constraints/row_table.hpp"
#include "engine/core/scratch_matrix.hpp"
#include "engine/core/zeroed_columns.hpp"
#include "engine/core/types.hpp"

namespace sinew {

class RowColumnCache {
 public:
  // Forget every column: H was refactorised.
  void reset();

  // Points columns[i] at y_i (3 free-DOF values) for every row of `rows`: kept, or solved by
  // one call `solve_many(B, X, wanted, pattern)` (X = H^-1 B, X given with B's size; `wanted`
  // as below; `pattern`, B's ZeroedColumns::Pattern, where each column's few non-zeros lie)
  // for all the rows without one. `free_index[n]` is the free index of global node n
  // or -1. The pointers hold until the next call or reset(). Returns the columns solved (3
  // per new node). Node columns are whole columns unless `partial`, unlike TouchedInverse's
  // G, which keeps only the touched nodes' rows.
  // With `partial`, the columns it solves are right only where W = J Y reads them: on the
  // free DOFs of the stencils of every row given since reset() (the wanted rows of
  // `solve_many(B, X, wanted)`, whose supernodal backward pass then skips the rest of L:
  // ~30 % of the solve on the creatures of the default demo), and elsewhere zero or garbage;
  // `solve_many` gets nullptr as `wanted` otherwise. See generations().
  template <typename SolveMany>
  int columns(const RowTable& rows, const std::vector<int>& free_index, int free_dofs, SolveMany&& solve_many,
              std::vector<const double*>& columns, int node_budget = 0, bool partial = false);
  static constexpr double kNodeColumnEntries = 1 << 24;  // 128 MB of node columns at most

  // Per row of the last call, the generation of its column: the count of partial solving
  // calls since reset() when it was solved, kComplete for a whole column. A column of generation g is
  // right on the stencils of every row of the calls up to g, so W_ij = J_i y_j = J_j y_i is
  // read from whichever of y_i, y_j has the later generation (Delassus::build_direct).
  static constexpr long kComplete = std::numeric_limits<long>::max();
  const std::vector<long>& generations() const { return m_generations; }
  // Whether every column of the last call is whole (H^-1 J^T itself, usable beyond W).
  bool complete() const { return m_complete; }

  int size() const { return static_cast<int>(m_index.size()); }
  // Whether the last call gave every row the very column the call before it gave (the same
  // keys in the same order, each column kept, none derived): W = J Y is then unchanged.
  bool same_columns_as_previous_call() const { return m_same_as_previous; }
  // Whether `rows` are the last call's rows bit for bit (keys, stencils and Jacobians, in
  // order) with no reset() since: that call's columns, still where it pointed them, are
  // the ones a call would give, and a W formed from them stands. Lets a caller skip the
  // call (and its lookups) on SQP iterations that keep their rows: the resting creature's
  // contacts on their plane.
  bool repeats_last_call(const RowTable& rows) const;
  // Free nodes holding node columns (0 after reset()).
  int node_count() const { return static_cast<int>(m_nodes.size()); }

 private:
  struct Entry {
    std::vector<int> nodes;
    std::vector<Vec3> jac;
    VecX y;
    long last_call = 0;  // the call that last used or solved it
    long generation = kComplete;
  };
  bool matches(const Entry& entry, const RowTable& rows, int i, int free_dofs) const;
  // Drops the entries the last call did not use, once they outnumber the rows: a
  // factorisation kept for several steps would otherwise keep every row it ever saw.
  void evict(int rows);
  void store(const RowTable& rows, int i, const double* y, int free_dofs, long generation);
  // Adds the free DOFs of every row's stencil not wanted yet to m_wanted.
  void want_stencils(const RowTable& rows, const std::vector<int>& free_index, int free_dofs);
  // Free slots enough for `entries` entries in all. After each call at most its rows stay
  // (evict), so a call of m rows holds at most m_before + m: with 2 m slots ready, and each
  // slot's column kept once used, the cache allocates only when it holds more entries at
  // once than ever before.
  void ensure_slots(int entries);
  // Solves the rows of m_missing and the node columns of m_new_nodes in one call and
  // stores them.
  template <typename SolveMany>
  void solve_missing(const RowTable& rows, const std::vector<int>& free_index, int free_dofs, SolveMany& solve_many,
                     std::vector<const double*>& columns, bool partial);
  // Node columns: the free nodes of the energy rows not yet held (m_new_nodes), and
  // whether every free node of row i has (or is about to have) its columns.
  // Empties m_new_nodes again when they exceed the budget (see the class comment).
  void collect_new_nodes(const RowTable& rows, const std::vector<int>& free_index, int free_dofs, int node_budget);
  bool has_node_columns(const RowTable& rows, const std::vector<int>& free_index, int i) const;
  // y_i from node columns for the rows of m_derived (in parallel, one row each).
  void combine_node_columns(const RowTable& rows, const std::vector<int>& free_index, int free_dofs,
                            std::vector<const double*>& columns);

  // The entry of a key, or nullptr.
  Entry* find(uint64_t key);

  // Entries live in m_slots and are recycled through m_free_slots with their buffers, so
  // that a warm cache allocates nothing; m_index maps keys to slots, sorted by key.
  std::deque<Entry> m_slots;  // a deque: growing it moves no entry (columns[] point into them)
  std::vector<int> m_free_slots;
  std::vector<std::pair<uint64_t, int>> m_index;
  long m_call = 0;
  std::vector<int> m_missing;
  std::vector<uint64_t> m_kept;
  ZeroedColumns m_B;
  ScratchMatrix m_X;
  // Node columns: m_node_slot[f] is free node f's position in m_nodes (its 3 columns at
  // 3 slot in m_node_columns) or -1; rows derived from them this call, and their columns.
  std::vector<int> m_node_slot, m_nodes, m_new_nodes, m_derived;
  bool m_nodes_chosen = false;  // by the first call since reset()
  // The keys of the last call in order, and whether each of its columns was an entry's
  // (kept or stored; not derived): what same_columns_as_previous_call compares against.
  std::vector<uint64_t> m_previous_keys, m_sorted_keys;
  bool m_previous_from_entries = false, m_same_as_previous = false;
  // The last call's stencils (repeats_last_call); false after reset().
  std::vector<int> m_previous_begin, m_previous_nodes;
  std::vector<Vec3> m_previous_jac;
  // False in a copy or a moved-to cache too: the caller's column pointers from the last
  // call point into the original's entries and scratch (a State copied between Worlds).
  struct CallFlag {
    bool value = false;
    CallFlag() = default;
    CallFlag(const CallFlag&) {}
    CallFlag(CallFlag&&) noexcept {}
    CallFlag& operator=(const CallFlag&) { value = false; return *this; }
    CallFlag& operator=(CallFlag&&) noexcept { value = false; return *this; }
  };
  CallFlag m_have_previous_call;
  // Partial columns: the solving calls since reset(), the DOFs they were right on, the
  // node columns' generation; the last call's generations.
  long m_generation = 0;
  std::vector<int> m_wanted;       // in the order first wanted (solve_many takes any order)
  std::vector<char> m_is_wanted;   // per free DOF; grows once, to the system's size
  long m_node_generation = kComplete;
  std::vector<long> m_generations;
  bool m_complete = true;
  void remember_call(const RowTable& rows);
  ScratchMatrix m_node_columns, m_derived_columns;
};

template <typename SolveMany>
int RowColumnCache::columns(const RowTable& rows, const std::vector<int>& free_index, int free_dofs,
                            SolveMany&& solve_many, std::vector<const double*>& columns, int node_budget,
                            bool partial) {
  const int m = rows.size();
  const bool node_columns = node_budget > 0;
  ++m_call;
  ensure_slots(2 * m);
  columns.assign(m, nullptr);
  m_missing.clear();
  m_kept.clear();
  m_new_nodes.clear();
  m_derived.clear();
  if (node_columns) m_node_slot.resize(free_dofs / 3, -1);  // reset() leaves every entry -1
  if (node_columns && !m_nodes_chosen) collect_new_nodes(rows, free_index, free_dofs, node_budget);
  m_generations.assign(m, kComplete);
  for (int i = 0; i < m; ++i) {
    Entry* entry = find(rows.key[i]);
    if (entry && matches(*entry, rows, i, free_dofs)) {
      entry->last_call = m_call;
      columns[i] = entry->y.data();
      m_generations[i] = entry->generation;
      m_kept.push_back(rows.key[i]);
    } else if (node_columns && rows.kind[i] == RowKind::Energy && has_node_columns(rows, free_index, i)) {
      m_derived.push_back(i);
    } else {
      m_missing.push_back(i);
    }
  }
  const int solved = static_cast<int>(m_missing.size() + 3 * m_new_nodes.size());
  if (solved > 0) solve_missing(rows, free_index, free_dofs, solve_many, columns, partial);
  if (!m_derived.empty()) combine_node_columns(rows, free_index, free_dofs, columns);
  for (const int i : m_derived) m_generations[i] = m_node_generation;
  m_complete = std::all_of(m_generations.begin(), m_generations.end(), [](long g) { return g == kComplete; });
  remember_call(rows);
  evict(m);
  return solved;
}

template <typename SolveMany>
void RowColumnCache::solve_missing(const RowTable& rows, const std::vector<int>& free_index, int free_dofs,
                                   SolveMany& solve_many, std::vector<const double*>& columns, bool partial) {
  const int row_count = static_cast<int>(m_missing.size()), node_count = static_cast<int>(m_new_nodes.size());
  const int solved = row_count + 3 * node_count;
  Eigen::Map<MatX> B = m_B.view(free_dofs, solved), X = m_X.view(free_dofs, solved);
  const ZeroedColumns::ClearOnExit clear_B{m_B};
  for (int k = 0; k < row_count; ++k) {
    const int i = m_missing[k];
    for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e)
      if (const int f = free_index[rows.nodes[e]]; f >= 0)
        for (int c = 0; c < 3; ++c) m_B.add(B, 3 * f + c, k, rows.jac[e][c]);
  }
  for (int k = 0; k < node_count; ++k)
    for (int c = 0; c < 3; ++c) m_B.set(B, 3 * m_new_nodes[k] + c, row_count + 3 * k + c, 1.0);
  long generation = kComplete;
  if (partial) {
    want_stencils(rows, free_index, free_dofs);
    generation = ++m_generation;
  }
  solve_many(B, X, partial ? &m_wanted : nullptr, &m_B.pattern(solved));
  for (const int i : m_missing) m_generations[i] = generation;
  if (node_count > 0) {  // only on the first call after reset(): nothing held yet
    m_node_generation = generation;
    m_node_columns.view(free_dofs, 3 * node_count) = X.rightCols(3 * node_count);
    for (int k = 0; k < node_count; ++k) {
      m_node_slot[m_new_nodes[k]] = static_cast<int>(m_nodes.size());
      m_nodes.push_back(m_new_nodes[k]);
    }
  }
  std::sort(m_kept.begin(), m_kept.end());
  for (int k = 0; k < row_count; ++k) {
    const int i = m_missing[k];
    columns[i] = X.col(k).data();
    // A key kept for another row of this call keeps its entry: columns[] points into it.
    if (!std::binary_search(m_kept.begin(), m_kept.end(), rows.key[i])) store(rows, i, columns[i], free_dofs, generation);
  }
}

}  // namespace sinew
