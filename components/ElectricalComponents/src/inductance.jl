# dyadc's own Julia for ElectricalComponents (names as Dyad's package has them).

# Position of entry (r, c), r <= c, of the upper triangle of an N x N matrix listed row by row:
# row r starts after the N + (N - 1) + ... + (N - r + 2) entries of the rows above it.
upper_triangle_index(r, c, N) = div((r - 1) * (2 * N - r + 2), 2) + c - r + 1

# The symmetric N x N inductance matrix whose upper triangle, row by row, is the vector L
# (self inductances on the diagonal, couplings off it): Lm[j, k] = Lm[k, j].
build_inductance_matrix(L, N) = [L[upper_triangle_index(min(j, k), max(j, k), N)] for j in 1:N, k in 1:N]
