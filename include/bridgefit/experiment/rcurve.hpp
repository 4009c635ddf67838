#pragma once
// R curves from test records (PHYSICS.md section 8), docs/RCURVE_METHODS.md.
//
//   experiment::RCurveOptions options;
//   options.method = experiment::RMethod::kMbt;
//   options.specimen = scene.specimen;  options.material = scene.material;
//   experiment::RCurveResult result = experiment::ComputeRCurve(record, options);
//   std::cout << result.BriefReport();
//
// Methods:
//   energy      dU = int_1^2 P dd - (P2 d2 - P1 d1)/2 between two rows, R = dU/(B da)
//   mbt         DCB modified beam theory: G = 3 P d / (2 b (a + |Delta|)), Delta from
//               the x-intercept of C^(1/3) against a (ASTM D5528)
//   cc          DCB compliance calibration: C = k a^n (log-log fit), G = n P d / (2 b a)
//   lefm        CT: G = K^2/E' with E399 K; DCB: G from the beam theory of the
//               specimen module (corrected beam with G13, else Kanninen)
//   equivalent  crack length from the compliance (no crack-length column needed):
//               CT: Saxena-Hudak inverse + E399; DCB: beam compliance inverse
//               with the flexural modulus calibrated at a0 + |Delta|
// Every row that does not give an R point is counted under a reason.

#include <map>
#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/experiment/cleaning.hpp"
#include "bridgefit/scene/scene.hpp"

namespace bridgefit::experiment {

enum class RMethod { kEnergy, kMbt, kComplianceCalibration, kLefm, kEquivalentCrack };
const char* RMethodName(RMethod method);  // energy | mbt | cc | lefm | equivalent
// Throws Error(kUsage) naming the accepted names.
RMethod ParseRMethod(const std::string& name);

struct RCurveOptions {
  RMethod method = RMethod::kEnergy;
  SpecimenSpec specimen;  // CT: W, B (thickness), notch; DCB: b (width), h (height), L
  MaterialSpec material;  // E (or E1, E2, G13); needed by lefm and equivalent

  // Noise levels (one standard deviation) of the record; NaN: estimated
  // from the record (robust second differences for load and displacement,
  // scatter about an 11-row moving average plus reading resolution for crack length).
  double load_noise = NAN;          // [N]
  double displacement_noise = NAN;  // [m]
  double crack_length_noise = NAN;  // [m]
  // Reported uncertainty = coverage_factor x standard uncertainty (2: ~95%).
  double coverage_factor = 2.0;

  // Energy method: each increment da >= max(min_crack_increment,
  // increment_resolution * sqrt(2) * crack_length_noise), so every da is
  // resolvable against the noise of its two end points: the crack-length
  // share of R's relative standard uncertainty is at most 1/increment_resolution.
  double min_crack_increment = 0.0;  // [m]
  double increment_resolution = 10.0;
  // Energy method on noisy records: > 0 replaces load, displacement and crack
  // length of the growth rows by local quadratic fits against time over
  // 2 smoothing_half_window + 1 rows (ASTM E647's incremental polynomial,
  // Savitzky-Golay on an uneven abscissa) before the energy balance; every
  // increment then spans at least one window, and the noise is propagated
  // through the fits' weights. 0: the rows as measured.
  int smoothing_half_window = 0;

  // Initiation: the initial compliance is fitted on the loading rows with
  // load between these fractions of the maximum load (before the maximum).
  double linear_fit_low = 0.1;
  double linear_fit_high = 0.5;
  double nonlinearity_tolerance = 0.01;  // NL: compliance above C0 (1 + tol)
  double offset_fraction = 0.05;         // 5% offset: compliance above C0 (1 + 0.05)

  // Validity window. Rows past max_crack_length are dropped (edge effect);
  // NaN: CT 0.9 W, DCB L - 4 h (when L is given).
  double max_crack_length = NAN;  // [m]
  // Record cleaning by named rules (cleaning.hpp): a reversal never ends the
  // test; unload-reload cycles, glitches, preload and post-failure rows are
  // counted by rule.
  CleaningOptions cleaning;

  // lefm/equivalent on CT: calibrate E' from the initial compliance at a0
  // (absorbs machine compliance and an uncertain modulus); false: use the
  // material's E'.
  bool calibrate_modulus = true;
  // DCB equivalent method: |Delta| for the flexural-modulus calibration;
  // NaN: from the MBT fit when the record has crack lengths, else Williams'
  // chi h when G13 is known, else 0 (noted: biased high).
  double crack_length_correction = NAN;  // [m]
  // DCB lefm/equivalent: use the shear modulus G13 (isotropic: E/(2(1+nu)))
  // in the arms (corrected beam / Timoshenko); false: Kanninen / simple beam.
  bool beam_shear = true;
  // DCB mbt/cc: ASTM D5528's large-displacement correction F and load-block
  // correction N (Williams): Delta or n fitted on C/N, G multiplied by F/N.
  //   F = 1 - 3/10 (d/a)^2 - 3/2 d t/a^2
  //   N = 1 - (L'/a)^3 - 9/8 (1 - (L'/a)^2) d t/a^2 - 9/35 (d/a)^2
  // t and L' describe the loading fixture, not the record; 0 keeps only the
  // arm-rotation terms in d/a. Off by default (plain D5528 reduction).
  bool large_displacement_correction = false;
  double load_block_offset = 0.0;       // t: loading-pin centre to arm mid-plane [m]
  double load_block_half_length = 0.0;  // L': loading-pin centre to the block's inner edge [m]
  // DCB mbt/cc: the compliance calibration taken as given instead of fitted
  // on this record (NaN: fitted). A fit reduces the model's own record with
  // the data's constants (as-data R), so the calibration's error - noise in
  // the data's compliance fit, or a row distribution unlike the model's -
  // is the same on both sides and cancels: R = 3 P d / (2 b (a + |Delta|))
  // differs between them only through P d at the crack length.
  double given_mbt_delta = NAN;     // [m], Delta as fitted (signed)
  double given_cc_exponent = NAN;   // n of C = k a^n

  bool IsValid(std::string* why) const;
};

// What set the energy method's smallest crack increment `floor` [m] (the
// larger of min_crack_increment and the crack readings' scatter floor): the
// option, where it is at least the floor (a smaller one lowers it); else
// the scatter, which smoothing lowers; a smoothed run: neither (its
// increments meet their own noise). The one rule behind the way out that
// rcurve and fit name when too few increments are resolvable.
enum class EnergyIncrementLimit { kAsked, kScatter, kSmoothed };
EnergyIncrementLimit EnergyIncrementLimitOf(const RCurveOptions& options, double floor);

struct DroppedRows {
  std::string reason;
  int count = 0;
};

struct Initiation {
  double initial_compliance = NAN;    // C0 [m/N], fitted
  double displacement_offset = NAN;   // d0 [m]: d = d0 + C0 P on the linear part
  int nonlinearity_row = -1;          // NL (deviation from linearity)
  int offset_row = -1;                // 5% offset, or max load if it comes first
  int max_load_row = -1;
  int visual_row = -1;                // first row with crack growth (crack lengths)
  double R_nonlinearity = NAN;        // [J/m^2] from the method at NL, where defined
  double R_offset = NAN;              // [J/m^2] at the 5% offset / max point
};

struct RCurveResult {
  RCurve curve;                      // method, a [m], R [J/m^2], expanded uncertainty
  std::vector<double> crack_growth;  // a - a0 [m] per point
  std::vector<double> load;          // P [N] per point (end row for energy)
  std::vector<double> displacement;  // [m] per point
  std::vector<int> rows;             // record row per point (end row for energy)
  int points_used = 0;
  std::vector<DroppedRows> dropped;  // rows giving no point, by reason
  std::vector<std::string> notes;    // cleaning and assumptions, in words
  std::vector<std::string> warnings; // what may make the numbers wrong (CLI: stderr)
  // Record rows (0-based) the cleaning kept on the envelope, before the
  // validity window, with rows whose only fault is a missing crack reading:
  // the rows a load-displacement fit should use.
  std::vector<int> clean_rows;
  Initiation initiation;
  double load_noise = NAN;           // noise levels used [N], [m], [m]
  double displacement_noise = NAN;
  double crack_length_noise = NAN;
  std::map<std::string, double> figures;  // fit constants (SI): mbt_delta_m, cc_n, ...
  double wall_s = 0.0;

  int DroppedTotal() const;
  std::string BriefReport() const;
};

// Throws Error (kInput) for bad records and options; see docs/RCURVE_METHODS.md.
RCurveResult ComputeRCurve(const ExperimentRecord& record, const RCurveOptions& options);

// Crack lengths measured on images (e.g. `bridgefit dic --csv`) put into a
// record whose `images` column names the image taken at a row. Frames are
// matched to rows by file name (without folders); frames without a crack
// length (the reference) are skipped. Every row gets the crack length
// interpolated linearly in time (row index without a time column) between
// the matched frames around it; rows before the first such frame take its
// value (the crack has not grown before it) and rows after the last are
// removed (no measurement). What was done is appended to `notes`. Throws
// Error (kInput, naming `source`) when fewer than two frames match.
ExperimentRecord CrackLengthFromFrames(const ExperimentRecord& record,
                                       const std::vector<std::string>& frame_images,
                                       const std::vector<double>& frame_crack_lengths,
                                       const std::string& source, std::vector<std::string>* notes);

// ---- building blocks (exposed for tests) ---------------------------------
// Least-squares non-decreasing fit (pool adjacent violators, equal weights).
std::vector<double> IsotonicIncreasing(const std::vector<double>& values);
// Robust noise sigma of a smooth signal: 1.4826 MAD of second differences / sqrt(6).
double RobustNoiseSigma(const std::vector<double>& values);
// Robust scatter of x about its centred moving average of 2 half_window + 1
// rows: RMS of the residuals (heavy tails count), corrected to the sigma of
// white noise.
double ScatterAboutMovingAverage(const std::vector<double>& values, int half_window);

// Energy released between rows i < j of (P, d): int P dd (trapezoids) minus
// the change of the stored energy P d / 2 (elastic unloading to the origin).
double EnergyReleased(const std::vector<double>& load, const std::vector<double>& displacement,
                      int first_row, int last_row);

// Local quadratic regression of y on x at one row: the fitted value there is
// sum_m weights[m] y[first_row + m], over the 2 half_window + 1 rows centred
// on `row`, shifted to stay inside [first, last] (all of it when shorter;
// a line or a mean when fewer than 3 distinct x).
struct LocalWeights {
  int first_row = 0;
  std::vector<double> weights;
};
LocalWeights LocalQuadraticWeights(const std::vector<double>& x, int first, int last, int row,
                                   int half_window);

}  // namespace bridgefit::experiment
