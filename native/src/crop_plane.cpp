#include "meshmark/crop_plane.h"
#include "meshmark/error.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace meshmark {

CroppedMesh crop_plane(const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P, const Eigen::Vector3d& normal,
                       double fraction) {
  if (!(fraction >= 0 && fraction < 1)) {
    std::ostringstream s;
    s << "crop fraction must be in [0, 1), got " << fraction;
    throw MeshError(s.str());
  }
  const double len = normal.norm();
  if (!(len > 0) || !std::isfinite(len)) throw MeshError("crop plane normal must be a finite non-zero vector");
  const Eigen::Vector3d nrm = normal / len;
  const Index n = static_cast<Index>(V.rows());
  const Offset m = P.n_faces();
  std::vector<double> s(static_cast<size_t>(n));
  double smin = std::numeric_limits<double>::infinity(), smax = -smin;
  for (Index i = 0; i < n; ++i) s[i] = V.row(i).dot(nrm.transpose());
  for (Offset c = 0; c < P.n_corners(); ++c) {
    smin = std::min(smin, s[P.indices[c]]);
    smax = std::max(smax, s[P.indices[c]]);
  }
  const double thr = smax - fraction * (smax - smin);
  std::vector<Index> remap(static_cast<size_t>(n), -1);
  std::vector<char> keepf(static_cast<size_t>(m), 1);
  Offset nf = 0, nc = 0;
  for (Offset f = 0; f < m; ++f) {
    for (Offset c = P.offsets[f]; c < P.offsets[f + 1]; ++c)
      if (s[P.indices[c]] > thr) keepf[f] = 0;
    if (keepf[f]) {
      ++nf;
      nc += P.offsets[f + 1] - P.offsets[f];
      for (Offset c = P.offsets[f]; c < P.offsets[f + 1]; ++c) remap[P.indices[c]] = 0;
    }
  }
  if (nf == 0) throw MeshError("cropping would remove every face");
  CroppedMesh out;
  Index nk = 0;
  for (Index i = 0; i < n; ++i)
    if (remap[i] == 0) remap[i] = nk++;
  out.V.resize(nk, 3);
  out.kept.resize(nk);
  for (Index i = 0; i < n; ++i)
    if (remap[i] >= 0) {
      out.V.row(remap[i]) = V.row(i);
      out.kept[remap[i]] = i;
    }
  out.P.indices.resize(nc);
  out.P.offsets.resize(nf + 1);
  out.P.offsets[0] = 0;
  Offset j = 0, c2 = 0;
  for (Offset f = 0; f < m; ++f) {
    if (!keepf[f]) continue;
    for (Offset c = P.offsets[f]; c < P.offsets[f + 1]; ++c) out.P.indices[c2++] = remap[P.indices[c]];
    out.P.offsets[++j] = c2;
  }
  return out;
}

}  // namespace meshmark
