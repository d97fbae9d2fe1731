#include "meshmark/convolutional_code.h"

#include "meshmark/error.h"

#include <algorithm>
#include <limits>
#include <string>

namespace meshmark {

namespace {
void check(const std::vector<int>& g, int K) {
  if (K < 2 || K > 10) throw MeshError("convolutional code: constraint length K must be in 2..10, got " + std::to_string(K));
  if (g.empty()) throw MeshError("convolutional code: no generators");
  for (int x : g)
    if (x <= 0 || x >= (1 << K)) throw MeshError("convolutional code: generator " + std::to_string(x) + " does not fit K bits");
}

inline int parity(unsigned x) { return __builtin_parity(x); }
}  // namespace

std::vector<std::uint8_t> conv_encode(const std::vector<std::uint8_t>& u, const std::vector<int>& g, int K,
                                      bool tail_biting) {
  check(g, K);
  const int m = K - 1, n = static_cast<int>(g.size());
  const std::size_t L = u.size();
  unsigned state = 0;  // bit m-1 = previous input, bit 0 = oldest
  if (tail_biting)
    for (std::size_t i = L >= static_cast<std::size_t>(m) ? L - m : 0; i < L; ++i) state = ((u[i] & 1u) << (m - 1)) | (state >> 1);
  const std::size_t T = tail_biting ? L : L + m;
  std::vector<std::uint8_t> c(T * n);
  for (std::size_t t = 0; t < T; ++t) {
    const unsigned in = t < L ? (u[t] & 1u) : 0u;
    const unsigned reg = (in << m) | state;
    for (int j = 0; j < n; ++j) c[t * n + j] = static_cast<std::uint8_t>(parity(reg & static_cast<unsigned>(g[j])));
    state = reg >> 1;
  }
  return c;
}

namespace {
struct Trellis {
  int m, n, S;
  std::vector<unsigned> out;  // outputs of (state, input), bit j = generator j
  Trellis(const std::vector<int>& g, int K) : m(K - 1), n(static_cast<int>(g.size())), S(1 << (K - 1)), out(2 * S) {
    for (int s = 0; s < S; ++s)
      for (unsigned in = 0; in < 2; ++in) {
        const unsigned reg = (in << m) | static_cast<unsigned>(s);
        unsigned o = 0;
        for (int j = 0; j < n; ++j) o |= static_cast<unsigned>(parity(reg & static_cast<unsigned>(g[j]))) << j;
        out[2 * s + in] = o;
      }
  }
};

const double NEG = -std::numeric_limits<double>::infinity();

// One Viterbi pass over `steps` trellis steps; step k reads the soft values of code step t(k) and,
// if forced(k) >= 0, only admits that input bit. pm: start metrics in, final metrics out; dec:
// decision bits (steps x S).
template <class StepOf, class Forced>
void pass(const Trellis& T, const std::vector<double>& llr, int steps, StepOf t_of, Forced forced, std::vector<double>& pm,
          std::vector<std::uint8_t>& dec) {
  const int S = T.S, n = T.n, m = T.m;
  std::vector<double> nm(S), bm(1u << n);
  dec.assign(static_cast<std::size_t>(steps) * S, 0);
  for (int k = 0; k < steps; ++k) {
    const double* y = &llr[static_cast<std::size_t>(t_of(k)) * n];
    for (unsigned o = 0; o < (1u << n); ++o) {
      double s = 0;
      for (int j = 0; j < n; ++j) s += (o >> j & 1u) ? y[j] : -y[j];
      bm[o] = s;
    }
    const int f = forced(k);
    for (int ns = 0; ns < S; ++ns) {
      const int in = ns >> (m - 1);
      if (f >= 0 && in != f) {
        nm[ns] = NEG;
        continue;
      }
      const int p0 = (ns << 1) & (S - 1), p1 = p0 | 1;
      const double a = pm[p0] + bm[T.out[2 * p0 + in]], b = pm[p1] + bm[T.out[2 * p1 + in]];
      const bool pick1 = b > a;
      nm[ns] = pick1 ? b : a;
      dec[static_cast<std::size_t>(k) * S + ns] = pick1;
    }
    pm.swap(nm);
  }
}

// Trace back from state s over the last L steps of dec (steps total); writes u[t] for code step
// t(k); returns the state before the first of those steps.
template <class StepOf>
int traceback(const Trellis& T, const std::vector<std::uint8_t>& dec, int steps, int L, int s, StepOf t_of,
              std::vector<std::uint8_t>& u) {
  for (int k = steps - 1; k >= steps - L; --k) {
    u[t_of(k)] = static_cast<std::uint8_t>(s >> (T.m - 1));
    s = ((s << 1) & (T.S - 1)) | dec[static_cast<std::size_t>(k) * T.S + s];
  }
  return s;
}
}  // namespace

std::vector<std::uint8_t> viterbi_decode(const std::vector<double>& llr, const std::vector<int>& g, int K, int n_info,
                                         bool tail_biting, int wrap) {
  check(g, K);
  const Trellis T(g, K);
  const int m = T.m, n = T.n, S = T.S;
  if (n_info < 1) throw MeshError("viterbi: n_info must be >= 1");
  const int L = n_info;
  const int steps0 = tail_biting ? L : L + m;
  if (static_cast<long>(llr.size()) != static_cast<long>(steps0) * n)
    throw MeshError("viterbi: " + std::to_string(llr.size()) + " soft values given, expected " + std::to_string(steps0 * n));
  std::vector<std::uint8_t> dec, u(L);
  if (!tail_biting) {  // maximum likelihood from state 0 to state 0 (the zero tail)
    std::vector<double> pm(S, NEG);
    pm[0] = 0;
    pass(T, llr, steps0, [](int k) { return k; }, [L](int k) { return k >= L ? 0 : -1; }, pm, dec);
    std::vector<std::uint8_t> full(steps0);
    traceback(T, dec, steps0, steps0, 0, [](int k) { return k; }, full);
    std::copy(full.begin(), full.begin() + L, u.begin());
    return u;
  }
  // Tail-biting, wrap-around Viterbi: circular passes carrying the metrics over (at least `wrap`
  // steps of warm-up, whole turns), then one turn with decisions kept.
  const int turns = std::max(1, (std::max(wrap, 0) + L - 1) / L);
  auto circ = [L](int k) { return k % L; };
  std::vector<double> pm(S, 0.0);
  pass(T, llr, turns * L, circ, [](int) { return -1; }, pm, dec);
  double top = *std::max_element(pm.begin(), pm.end());
  for (double& x : pm) x -= top;  // keep the metrics small
  std::vector<double> pm_last = pm;
  pass(T, llr, L, circ, [](int) { return -1; }, pm_last, dec);
  int best = 0;
  for (int i = 1; i < S; ++i)
    if (pm_last[i] > pm_last[best]) best = i;
  const int start = traceback(T, dec, L, L, best, circ, u);
  (void)start;
  // Otherwise: exact tail-biting search from (to) the 8 best final states, and the path found.
  auto metric_of = [&](const std::vector<std::uint8_t>& v) {
    const std::vector<std::uint8_t> c = conv_encode(v, g, K, true);
    double s = 0;
    for (std::size_t i = 0; i < c.size(); ++i) s += c[i] ? llr[i] : -llr[i];
    return s;
  };
  std::vector<int> order(S);
  for (int i = 0; i < S; ++i) order[i] = i;
  const int n_cand = std::min(S, 8);
  std::partial_sort(order.begin(), order.begin() + n_cand, order.end(),
                    [&](int a, int b) { return pm_last[a] > pm_last[b]; });
  std::vector<std::uint8_t> best_u = u, v(L);
  double best_metric = metric_of(u);
  for (int c = 0; c < n_cand; ++c) {
    const int s0 = order[c];
    std::vector<double> q(S, NEG);
    q[s0] = 0;
    // the last m inputs must rebuild s0: input at step t >= L - m is bit (t - (L - m)) of s0
    pass(T, llr, L, [](int k) { return k; },
         [&](int k) { return k >= L - m ? (s0 >> (k - (L - m))) & 1 : -1; }, q, dec);
    if (q[s0] == NEG) continue;  // L < m and s0 inconsistent with itself
    traceback(T, dec, L, L, s0, [](int k) { return k; }, v);
    const double mv = metric_of(v);
    if (mv > best_metric) best_metric = mv, best_u = v;
  }
  return best_u;
}

}  // namespace meshmark
