#pragma once
// Columns laid out as rows: dst[d * dst_stride + b] = columns[b][d] for d < height and
// b < count. The active-set PGS (lcp_active_set.cpp) holds A's columns of T so, each row of
// the result then a run over the columns. Copies only: the bits are the sources'.
namespace sinew {

void transpose_columns(const double* const* columns, int count, int height, double* dst,
                       long dst_stride);

}  // namespace sinew
