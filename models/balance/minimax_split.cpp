#include "balance/minimax_split.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <utility>

namespace rt {

std::vector<int> minimaxSplit(const PartCosts& c, int count, int minCells) {
    const int m = c.m;
    if (count < 1 || minCells < 1 || int64_t(count) * minCells > m || c.cost.size() != size_t(m + 1) * size_t(m + 1))
        throw std::invalid_argument("minimaxSplit: the parts do not fit the grid");
    // best[j]: the cheapest (dearest part, sum of squares) over k parts that end at edge j.
    using Key = std::pair<double, double>;
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<Key> best(size_t(m + 1), {inf, inf}), next(size_t(m + 1));
    best[0] = {0, 0};
    std::vector<std::vector<int>> from(size_t(count), std::vector<int>(size_t(m + 1), -1));
    for (int k = 0; k < count; ++k) {
        // Part k + 1 ends at j; the count - k - 1 parts after it need their cells.
        const int jLo = (k + 1) * minCells, jHi = m - (count - k - 1) * minCells;
        std::fill(next.begin(), next.end(), Key{inf, inf});
        for (int j = jLo; j <= jHi; ++j) {
            Key bj{inf, inf};
            int bi = -1;
            for (int i = k * minCells; i <= j - minCells; ++i) {
                if (best[size_t(i)].first == inf) continue;
                const double x = c(i, j);
                const Key key{std::max(best[size_t(i)].first, x), best[size_t(i)].second + x * x};
                if (key < bj) {
                    bj = key;
                    bi = i;
                }
            }
            next[size_t(j)] = bj;
            from[size_t(k)][size_t(j)] = bi;
        }
        std::swap(best, next);
    }
    std::vector<int> edges(size_t(count + 1));
    edges[size_t(count)] = m;
    for (int k = count - 1; k >= 0; --k) edges[size_t(k)] = from[size_t(k)][size_t(edges[size_t(k + 1)])];
    return edges;
}

}  // namespace rt
