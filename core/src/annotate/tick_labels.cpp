// Colour-bar ticks and their labels (contracts in annotate.h). Labels are made from the exact
// decimal value of each tick, rounded once at a chosen decimal place, so a label is always
// its tick to within half a unit of its last digit, whatever the range's magnitude or width.
#include <tessera/annotate.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace tessera {
namespace {

/// Labels longer than this (a narrow range far from zero) are written as a base and offsets.
constexpr std::size_t kMaxPlainLabel = 12;
/// Longest base-and-offset label with the ticks rounded at units, where the step allows coarser.
constexpr std::size_t kMaxOffsetLabel = 2 * kMaxPlainLabel + 3;
/// Below the largest tick's first digit, 17 more places tell any two doubles apart.
constexpr int kDoubleDigits = 17;

/// A double's absolute value exactly, as decimal digits: |v| = digits x 10^place, without
/// leading or trailing zeros ("" for zero).
struct Decimal {
  std::string digits;
  int place = 0;
  bool negative = false;
  bool zero() const { return digits.empty(); }
  /// The place of the first digit (0 for zero).
  int lead() const { return zero() ? 0 : place + static_cast<int>(digits.size()) - 1; }
};

Decimal exact_decimal(double v) {
  Decimal d;
  d.negative = std::signbit(v);
  v = std::abs(v);
  if (v == 0.0 || !std::isfinite(v)) return d;
  // A double has as many decimal digits after the point as binary ones: at most 1074
  const int frac = std::clamp(52 - std::ilogb(v), 0, 1074);
  char buf[1500];  // at most 309 integer digits, the point and 1074 more
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, frac);
  if (ec != std::errc()) return d;
  for (const char* p = buf; p != end; ++p)
    if (*p != '.') d.digits += *p;
  d.place = -frac;
  d.digits.erase(0, d.digits.find_first_not_of('0'));
  const std::size_t last = d.digits.find_last_not_of('0');
  d.place += static_cast<int>(d.digits.size() - 1 - last);
  d.digits.erase(last + 1);
  return d;
}

/// Digit strings without leading zeros ("0" for zero) as unsigned integers.
int compare(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return a.size() < b.size() ? -1 : 1;
  return a.compare(b) < 0 ? -1 : a == b ? 0 : 1;
}

void increment(std::string& s) {
  for (std::size_t i = s.size(); i-- > 0;) {
    if (s[i] != '9') {
      ++s[i];
      return;
    }
    s[i] = '0';
  }
  s.insert(s.begin(), '1');
}

std::string without_leading_zeros(std::string s) {
  s.erase(0, std::min(s.find_first_not_of('0'), s.size() - 1));
  return s.empty() ? "0" : s;
}

/// a - b for a >= b.
std::string difference(const std::string& a, const std::string& b) {
  std::string out = a;
  int borrow = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::size_t k = out.size() - 1 - i;
    int d = (a[k] - '0') - borrow - (i < b.size() ? b[b.size() - 1 - i] - '0' : 0);
    borrow = d < 0 ? 1 : 0;
    out[k] = static_cast<char>('0' + d + 10 * borrow);
  }
  return without_leading_zeros(out);
}

/// The smallest multiple of 10^m that is >= a.
std::string ceil_to_power(const std::string& a, std::size_t m) {
  if (a == "0") return a;
  if (m >= a.size()) return "1" + std::string(m, '0');
  std::string head = a.substr(0, a.size() - m);
  if (a.find_first_not_of('0', a.size() - m) != std::string::npos) increment(head);
  return without_leading_zeros(head + std::string(m, '0'));
}

/// |x| rounded to a multiple of 10^place, ties to even: the multiple's digits ("0" for none).
std::string rounded(const Decimal& x, int place) {
  if (x.zero()) return "0";
  if (place <= x.place) return x.digits + std::string(x.place - place, '0');
  const int n = static_cast<int>(x.digits.size());
  const int drop = place - x.place;  // digits below the place
  if (drop > n) return "0";
  std::string keep = x.digits.substr(0, n - drop);
  const char first = x.digits[n - drop];
  const bool rest = drop > 1;  // the last digit is never 0, so any digit after `first` makes it more
  const bool odd = !keep.empty() && (keep.back() - '0') % 2 == 1;
  if (keep.empty()) keep = "0";
  if (first > '5' || (first == '5' && (rest || odd))) increment(keep);
  return without_leading_zeros(keep);
}

/// The digits of a value that is a multiple of 10^place, as a Decimal (for the base and offsets).
Decimal decimal_of(const std::string& digits, int place, bool negative) {
  Decimal d;
  d.negative = negative;
  if (digits == "0") return d;
  const std::size_t last = digits.find_last_not_of('0');
  d.digits = digits.substr(0, last + 1);
  d.place = place + static_cast<int>(digits.size() - 1 - last);
  return d;
}

enum class Notation { Fixed, Scientific };

/// `digits` x 10^place (place <= 0) in fixed point: "0.25", "101324.6", "320".
std::string fixed_text(std::string digits, int place, bool negative) {
  const std::size_t decimals = static_cast<std::size_t>(-place);
  if (decimals > 0) {
    if (digits.size() <= decimals) digits.insert(0, decimals + 1 - digits.size(), '0');
    digits.insert(digits.size() - decimals, ".");
  }
  const bool zero = digits.find_first_not_of("0.") == std::string::npos;
  return negative && !zero ? "-" + digits : digits;
}

/// A mantissa's digits with the exponent of its first: "1.5e+06", "2.0e-05", "7e+300".
std::string scientific_text(const std::string& digits, int exponent, bool negative) {
  std::string s = negative ? "-" : "";
  s += digits[0];
  if (digits.size() > 1) s += "." + digits.substr(1);
  char buf[16];
  std::snprintf(buf, sizeof buf, "e%c%02d", exponent < 0 ? '-' : '+', std::abs(exponent));
  return s + buf;
}

/// x as a label resolving 10^e: fixed point down to 10^min(e, 0); or scientific with
/// `decimals` mantissa decimals (printf's %.*e, exact; finer than 10^e for a smaller x), "0"
/// for zero.
std::string label_text(const Decimal& x, int e, Notation n, int decimals) {
  if (n == Notation::Fixed) return fixed_text(rounded(x, std::min(e, 0)), std::min(e, 0), x.negative);
  if (x.zero()) return "0";
  const int place = x.lead() - decimals;  // <= e: x's first digit is at most the largest tick's
  std::string r = rounded(x, place);
  const int exponent = place + static_cast<int>(r.size()) - 1;  // one more where 9.96 became 10.0
  r.resize(static_cast<std::size_t>(decimals) + 1);
  return scientific_text(r, exponent, x.negative);
}

/// Fixed point for magnitudes 0.001 to 99999 and where it is shorter, else scientific.
Notation notation_for(const Decimal& m, int e) {
  if (m.zero() || (m.lead() >= -3 && m.lead() <= 4)) return Notation::Fixed;
  const std::string f = label_text(m, e, Notation::Fixed, 0);
  const std::string s = label_text(m, e, Notation::Scientific, std::max(0, m.lead() - e));
  return f.size() < s.size() ? Notation::Fixed : Notation::Scientific;
}

/// Every x at 10^e in the notation `m` (the largest magnitude) chooses.
std::vector<std::string> plain_labels(const std::vector<Decimal>& xs, const Decimal& m, int e) {
  const Notation n = notation_for(m, e);
  std::vector<std::string> out;
  for (const Decimal& x : xs) out.push_back(label_text(x, e, n, std::max(0, m.lead() - e)));
  return out;
}

bool all_distinct(const std::vector<std::string>& labels) {
  for (std::size_t i = 1; i < labels.size(); ++i)
    if (labels[i] == labels[i - 1]) return false;
  return true;
}

std::size_t longest(const std::vector<std::string>& labels) {
  std::size_t n = 0;
  for (const std::string& s : labels) n = std::max(n, s.size());
  return n;
}

/// A value alone and exact, in its own notation or in scientific: "101325", "1e+16", "-2.5e-07".
std::string exact_text(const Decimal& x, bool scientific) {
  const Notation n = scientific ? Notation::Scientific : notation_for(x, x.place);
  return label_text(x, x.place, n, std::max(0, x.lead() - x.place));
}

/// Ticks of one sign as "base + offset" at 10^e: the base is the multiple of the largest
/// power of ten that lies between the ticks (rounded at 10^e), the offsets are exact. Fixed
/// point claims units, so for e > 0 the caller asks for `scientific` throughout.
std::vector<std::string> offset_labels(const std::vector<Decimal>& xs, int e, bool scientific) {
  std::vector<std::string> mags;
  for (const Decimal& x : xs) mags.push_back(rounded(x, e));
  const auto by_value = [](const std::string& a, const std::string& b) { return compare(a, b) < 0; };
  const std::string lo = *std::min_element(mags.begin(), mags.end(), by_value);
  const std::string hi = *std::max_element(mags.begin(), mags.end(), by_value);
  std::string base = lo;
  for (std::size_t m = hi.size(); m > 0; --m) {
    const std::string c = ceil_to_power(lo, m);
    if (compare(c, hi) <= 0) {
      base = c;
      break;
    }
  }
  const bool negative = xs.front().negative;
  const std::string base_text = exact_text(decimal_of(base, e, negative), scientific);

  // Offsets: one notation for all, chosen by the largest
  std::vector<Decimal> offsets;
  std::vector<bool> above;  // the tick's magnitude is above the base's
  Decimal largest;
  for (const std::string& a : mags) {
    const bool up = compare(a, base) >= 0;
    offsets.push_back(decimal_of(up ? difference(a, base) : difference(base, a), e, false));
    above.push_back(up);
    if (!offsets.back().zero() && (largest.zero() || offsets.back().lead() > largest.lead())) largest = offsets.back();
  }
  const Notation n = scientific ? Notation::Scientific : notation_for(largest, e);
  std::vector<std::string> out;
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    if (offsets[i].zero()) {
      out.push_back(base_text);
      continue;
    }
    // value = sign * (base + (a - base)): for negative ticks a larger magnitude is a minus
    const bool plus = above[i] != negative;
    // Digits down to 10^e and no further: the tick was rounded there
    out.push_back(base_text + (plus ? " + " : " - ") + label_text(offsets[i], e, n, offsets[i].lead() - e));
  }
  return out;
}

/// floor(log10(b - a)) for a < b without overflow, a difference a hair below a power of ten
/// counting as that power (the caller refines where labels then coincide).
int place_of_difference(double a, double b) {
  if (!(a < b)) return -1100;  // no difference: the finest place (the caller clamps)
  const double d = b - a;
  const double lg = std::isfinite(d) ? std::log10(d) : std::log10(0.5 * b - 0.5 * a) + std::log10(2.0);
  return static_cast<int>(std::floor(lg + 1e-9));
}

double nice_step(double lo, double hi, int target) {
  // Half of each end where their difference overflows (a range of +-1e308)
  const double raw = std::isfinite(hi - lo) ? (hi - lo) / target : 2.0 * ((0.5 * hi - 0.5 * lo) / target);
  if (!(raw > 0.0) || !std::isfinite(raw)) return 0.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double norm = raw / mag;
  const double step = (norm < 1.5 ? 1.0 : norm < 3.0 ? 2.0 : norm < 7.0 ? 5.0 : 10.0) * mag;
  // Multiples of the step must still be exact enough to tell apart
  if (!(step > 0.0) || !std::isfinite(step) || std::max(std::abs(lo), std::abs(hi)) / step > 1e12) return 0.0;
  return step;
}

}  // namespace

std::vector<double> colorbar_ticks(double lo, double hi, int target) {
  target = std::clamp(target, 2, 10);
  const double step = nice_step(lo, hi, target);
  if (step == 0.0) return {lo, hi};
  const double k0 = std::ceil(lo / step - 1e-9), k1 = std::floor(hi / step + 1e-9);
  if (!(k1 >= k0) || k1 - k0 > 2 * target + 1) return {lo, hi};
  std::vector<double> ticks;
  for (double k = k0; k <= k1; k += 1.0) {
    const double t = std::clamp(k * step, lo, hi);
    if (ticks.empty() || t > ticks.back()) ticks.push_back(t);
  }
  if (ticks.size() < 2) return {lo, hi};
  return ticks;
}

std::vector<std::string> colorbar_labels(const std::vector<double>& ticks, double lo, double hi) {
  if (ticks.empty()) return {};
  std::vector<Decimal> xs;
  for (const double t : ticks) xs.push_back(exact_decimal(t));
  // The largest magnitude (its first digit leads), and the finest place any tick has a digit
  Decimal m;
  int finest = 0;
  for (const Decimal& x : xs) {
    if (x.zero()) continue;
    if (m.zero() || x.lead() > m.lead()) m = x;
    finest = std::min(finest, x.place);
  }

  // One tick: the range's width resolves it, with at most kMaxPlainLabel characters
  if (xs.size() == 1) {
    int e = lo < hi ? std::max(place_of_difference(lo, hi), finest) : finest;
    std::vector<std::string> one = plain_labels(xs, m, e);
    while (one[0].size() > kMaxPlainLabel && e < m.lead()) one = plain_labels(xs, m, ++e);
    return one;
  }

  // Several: digits from the step, finer until neighbours differ (17 significant digits tell
  // distinct doubles apart; all of them, exact, always do)
  int e = place_of_difference(ticks[0], ticks[1]);
  for (std::size_t i = 2; i < ticks.size(); ++i)
    if (ticks[i - 1] < ticks[i]) e = std::min(e, place_of_difference(ticks[i - 1], ticks[i]));
  e = std::clamp(e, finest, m.lead() + 1);
  std::vector<std::string> labels = plain_labels(xs, m, e);
  while (!all_distinct(labels) && e > finest) {
    e = e > m.lead() - kDoubleDigits ? e - 1 : finest;
    labels = plain_labels(xs, m, e);
  }

  // Too long to read (a narrow range far from zero): a round base and offsets from it
  const bool one_sign = std::all_of(ticks.begin(), ticks.end(), [](double t) { return t > 0.0; }) ||
                        std::all_of(ticks.begin(), ticks.end(), [](double t) { return t < 0.0; });
  if (longest(labels) > kMaxPlainLabel && one_sign) {
    // A step above 1: the ticks at units where that stays short ("1e+16 + 10"), else
    // everything in scientific, whose digits say where they were rounded
    std::vector<std::string> offset = offset_labels(xs, std::min(e, 0), false);
    if (e > 0 && longest(offset) > kMaxOffsetLabel) offset = offset_labels(xs, e, true);
    if (all_distinct(offset)) return offset;
  }
  return labels;
}

std::string tick_label(double v, double step, double largest) {
  const Decimal x = exact_decimal(v);
  const Decimal l = exact_decimal(largest);
  const Decimal& m = l.zero() || x.lead() > l.lead() ? x : l;
  // Without a usable step, six significant digits (printf's %.6g)
  const int e =
      step > 0.0 && std::isfinite(step) ? static_cast<int>(std::floor(std::log10(step) + 1e-9)) : m.lead() - 5;
  return plain_labels({x}, m, e)[0];
}

}  // namespace tessera
