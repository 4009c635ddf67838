// The crack band: the grid points one frame's crack location reads, and the
// tracker that correlates exactly those (include/bridgefit/dic/sequence.hpp,
// crack_band_impl.hpp).
#include <algorithm>
#include <cmath>

#include "crack_band_impl.hpp"

namespace bridgefit::dic {

std::vector<char> CrackBandPoints(const DisplacementField& grid, const CrackSequenceOptions& o,
                                  const CrackBandReads& reads) {
  std::vector<char> on(grid.size(), 0);
  // Path scan: columns over the hint's extent (+- half a station), n within
  // the search half width plus the side windows' reach (crack_path.cpp).
  const double scan_half = o.path.search_half_width_px + o.path.gap_px + o.path.side_depth_px;
  const double scan_ds = 0.5 * o.path.station_spacing_px;
  // COD profile: stations every station spacing over [0, L], each reading the
  // points within 1.01 spacings along and band + side depth across (crack.cpp).
  const double cod_half = o.tip.band_half_width_px + o.tip.side_depth_px;
  const double cod_ds = 1.01 * o.tip.station_spacing_px;
  // Williams window: the fit radius plus one grid diagonal (the continuum
  // test reads each window point's 8 neighbours, crack_williams.cpp).
  const double disk = o.tip.fit_radius_px + reads.window_margin_px + 1.5 * o.correlation.step;
  const double scan_len = reads.scan ? reads.scan_line.Length() : 0;
  const double cod_len = reads.cod ? reads.cod_line.Length() : 0;
  for (size_t i = 0; i < grid.size(); ++i) {
    const double x = grid.x[i], y = grid.y[i];
    double s, n;
    bool in = false;
    if (reads.scan) {
      reads.scan_line.ToLocal(x, y, &s, &n);
      in = std::abs(n) <= scan_half && s >= -scan_ds && s <= scan_len + scan_ds;
    }
    if (!in && reads.cod) {
      reads.cod_line.ToLocal(x, y, &s, &n);
      in = std::abs(n) <= cod_half && s >= -cod_ds && s <= cod_len + cod_ds;
    }
    if (!in && reads.window) in = std::hypot(x - reads.window_x, y - reads.window_y) <= disk;
    on[i] = in ? 1 : 0;
  }
  return on;
}

namespace detail {

BandTracker::BandTracker(const CrackSequenceOptions& o, const CrackPathOptions& path_opt,
                         Correlator* c)
    : o_(o), path_opt_(path_opt), c_(c) {
  const DisplacementField& g = c->Grid();
  usable_.resize(g.size());
  for (size_t i = 0; i < g.size(); ++i)
    usable_[i] = g.status[i] != PointStatus::kMasked && g.status[i] != PointStatus::kCrackBand;
  have_line_ = o.has_line;
  scan_line_ = o.tip.line;
}

void BandTracker::Prepare() {
  if (!Enabled()) return;
  if (!have_line_) {  // no line and no path yet: the whole field
    active_.assign(usable_.size(), 1);
    c_->SetActive({});
    return;
  }
  CrackBandReads reads;
  reads.scan = o_.find_path;  // --fixed-line: no path scan
  reads.scan_line = scan_line_;
  if (have_last_) {
    reads.cod = true;
    reads.cod_line = last_line_;
    reads.window = last_window_;
    reads.window_x = last_cx_;
    reads.window_y = last_cy_;
    reads.window_margin_px = std::max(2.0 * o_.correlation.step, last_move_);
  }
  active_ = CrackBandPoints(c_->Grid(), o_, reads);
  c_->SetActive(active_);
}

// What the location of *r read beside the path scan: the COD windows about
// the line it used and its Williams window about its centre.
CrackBandReads BandTracker::LocationReads(const FrameResult& r) const {
  CrackBandReads reads;
  reads.cod = !r.tip.cod.s_px.empty();
  reads.cod_line = r.line_used;
  reads.window = r.tip.williams_window;
  r.line_used.FromLocal(r.tip.williams_centre_s_px, 0, &reads.window_x, &reads.window_y);
  return reads;
}

// The points the location of *r read (given its line and window) that
// were not correlated.
std::vector<char> BandTracker::Missing(const FrameResult& r) const {
  CrackBandReads reads = LocationReads(r);
  reads.scan = o_.find_path;  // --fixed-line: no path scan
  reads.scan_line = scan_line_;
  std::vector<char> need = CrackBandPoints(c_->Grid(), o_, reads);
  for (size_t i = 0; i < need.size(); ++i) need[i] = need[i] && usable_[i] && !active_[i];
  return need;
}

bool BandTracker::Lacks(const DisplacementField& field, const FrameResult& r) const {
  if (!Enabled()) return false;
  const std::vector<char> need = CrackBandPoints(c_->Grid(), o_, LocationReads(r));
  for (size_t i = 0; i < need.size(); ++i)
    if (need[i] && usable_[i] && field.status[i] == PointStatus::kMasked) return true;
  return false;
}

void BandTracker::Complete(DisplacementField* field, FrameResult* r) {
  if (!Enabled()) return;
  // Without a line and before a path: the whole field was correlated.
  if (have_line_) {
    auto any = [](const std::vector<char>& v) { return std::find(v.begin(), v.end(), 1) != v.end(); };
    std::vector<char> need = Missing(*r);
    for (int round = 0; round < 3 && any(need); ++round) {
      for (size_t i = 0; i < need.size(); ++i) active_[i] = active_[i] || need[i];
      CorrelationSummary summary = r->correlation;
      *field = c_->Extend(active_, &summary);
      FrameResult again;
      again.image = r->image;
      again.correlation = summary;
      LocateCrackInField(*field, o_, path_opt_, &again);
      *r = std::move(again);
      need = Missing(*r);
    }
    // Still short after three rounds (the path moved each time): flagged.
    r->tip_beyond_band = any(need);
    r->flagged = r->flagged || r->tip_beyond_band;
  }
  // Record what this frame read, for the next frame's prediction.
  if (r->tip.williams_window) {
    double cx, cy;
    r->line_used.FromLocal(r->tip.williams_centre_s_px, 0, &cx, &cy);
    if (last_window_) last_move_ = std::hypot(cx - last_cx_, cy - last_cy_);
    last_window_ = true;
    last_cx_ = cx;
    last_cy_ = cy;
  }
  if (r->tip.cod.s_px.size() > 0 || r->path.found) {
    have_last_ = true;
    last_line_ = r->line_used;
  }
  // Without a line: once a path is found it stands in for the line.
  if (!o_.has_line && r->path.found && r->tip.tip.found) {
    have_line_ = true;
    scan_line_ = r->line_used;
  }
}

}  // namespace detail
}  // namespace bridgefit::dic
