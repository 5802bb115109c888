// Ranks agree on the grid, mesh and field list of a firing call (publication_agreement.h).
#include "agreement/publication_agreement.h"

#include "data/domain_binding.h"
#include "data/hash64.h"

#include <tessera/field_view.h>
#include <tessera/message_text.h>
#include <tessera/number_text.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace tessera::insitu {
namespace {

static_assert(std::is_trivially_copyable_v<PublicationRecord>);

constexpr const char* kAxis = "ijk";

/// The coordinates of one axis are compared in chunks on the failure path: at most
/// kMaxChunks chunk hashes, then one chunk's values, travel from each of two ranks.
constexpr std::int64_t kMinChunk = 4096;
constexpr std::int64_t kMaxChunks = 65536;

/// At most this many bytes of a field list travel from each of two ranks on the failure path.
constexpr std::size_t kMaxFieldListBytes = std::size_t{1} << 20;

std::string rank_name(int r) { return "rank " + std::to_string(r); }

/// "axis j (coords[1])", "spacing[1] (j)"
std::string axis_label(int a) { return std::string("axis ") + kAxis[a]; }
std::string indexed(const char* what, int a) {
  return std::string(what) + "[" + std::to_string(a) + "] (" + kAxis[a] + ")";
}

template <class T>
std::string vec3(const T v[3]) {
  std::string s = "[";
  for (int a = 0; a < 3; ++a) {
    if (a) s += ", ";
    if constexpr (std::is_floating_point_v<T>) s += format_number(v[a]);  // two values that differ never print alike
    else s += std::to_string(v[a]);
  }
  s += ']';
  return s;
}

std::string dtype_text(std::int64_t d) {
  return d >= TESSERA_UINT8 && d <= TESSERA_FLOAT64 ? std::string(dtype_name(static_cast<DType>(d)))
                                                    : "dtype " + std::to_string(d);
}

std::string what_data(std::int64_t association) {
  return association == TESSERA_CELL ? "cell data (TESSERA_CELL)" : "vertex data (TESSERA_VERTEX)";
}

std::int64_t coord_count(const tessera_mesh& m, int a) {
  return m.global_dims[a] + (m.association == TESSERA_CELL ? 1 : 0);
}

// ---------------------------------------------------------------------------------------
// Field lists: sorted (name, dtype), serialised as [u32 length][name][i32 dtype] per field

struct FieldEntry {
  std::string_view name;
  std::int32_t dtype;
  std::int32_t association;  ///< the domain's associations[f], else the mesh's (as given)
  bool operator<(const FieldEntry& o) const {
    return name != o.name ? name < o.name : dtype != o.dtype ? dtype < o.dtype : association < o.association;
  }
};

/// Domain 0's field list, sorted; nothing when it cannot be read (the bind phase reports it).
std::optional<std::vector<FieldEntry>> field_list(const tessera_mesh* mesh, const tessera_domain* domains,
                                                  std::int64_t ndomains) {
  if (!domains || ndomains <= 0) return std::nullopt;
  const tessera_domain& d = domains[0];
  if (d.nfields < 0 || (d.nfields > 0 && !d.fields)) return std::nullopt;
  std::vector<FieldEntry> list;
  list.reserve(static_cast<std::size_t>(d.nfields));
  for (int f = 0; f < d.nfields; ++f) {
    if (!d.fields[f].name) return std::nullopt;
    std::int32_t dtype;
    static_assert(sizeof dtype == sizeof d.fields[f].dtype);
    std::memcpy(&dtype, &d.fields[f].dtype, sizeof dtype);  // any int a C caller stored
    std::int32_t assoc = 0;
    if (d.associations) std::memcpy(&assoc, &d.associations[f], sizeof assoc);
    else if (mesh) std::memcpy(&assoc, &mesh->association, sizeof assoc);
    list.push_back({d.fields[f].name, dtype, assoc});
  }
  std::sort(list.begin(), list.end());
  return list;
}

/// The list's bytes; with `limit`, only the whole entries that fit in it.
std::string serialised(const std::vector<FieldEntry>& list, std::size_t limit = std::string::npos) {
  std::string s;
  for (const FieldEntry& e : list) {
    const std::size_t bytes = 12 + e.name.size();
    if (s.size() + bytes > limit) break;
    const auto len = static_cast<std::uint32_t>(std::min<std::size_t>(e.name.size(), UINT32_MAX));
    s.append(reinterpret_cast<const char*>(&len), 4).append(e.name.substr(0, len));
    s.append(reinterpret_cast<const char*>(&e.dtype), 4);
    s.append(reinterpret_cast<const char*>(&e.association), 4);
  }
  return s;
}

std::vector<FieldEntry> parsed(const std::string& s) {
  std::vector<FieldEntry> list;
  std::size_t p = 0;
  while (p + 4 <= s.size()) {
    std::uint32_t len;
    std::memcpy(&len, s.data() + p, 4);
    if (p + 12 + len > s.size()) break;
    FieldEntry e{std::string_view(s).substr(p + 4, len), 0, 0};
    std::memcpy(&e.dtype, s.data() + p + 4 + len, 4);
    std::memcpy(&e.association, s.data() + p + 8 + len, 4);
    list.push_back(e);
    p += 12 + len;
  }
  return list;
}

std::string field_name(std::string_view name) {
  std::string q(1, '\'');  // (appends: GCC 12 warns falsely (-Wrestrict) on "'" + ...)
  return q.append(shown_value(name, 60)).append(1, '\'');
}

/// The first difference of two sorted lists, in words; "" if none.
std::string list_difference(const std::vector<FieldEntry>& mine, const std::vector<FieldEntry>& ref, int r,
                            int ref_rank) {
  const std::string who = rank_name(r), them = rank_name(ref_rank);
  for (std::size_t q = 0; q < std::max(mine.size(), ref.size()); ++q) {
    const bool has_mine = q < mine.size(), has_ref = q < ref.size();
    if (has_mine && has_ref && mine[q].name == ref[q].name) {
      if (mine[q].dtype != ref[q].dtype)
        return "field " + field_name(mine[q].name) + " is " + dtype_text(mine[q].dtype) + " on " + who + ", " +
               dtype_text(ref[q].dtype) + " on " + them;
      if (mine[q].association != ref[q].association)
        return "field " + field_name(mine[q].name) + " is " + what_data(mine[q].association) + " on " + who + ", " +
               what_data(ref[q].association) + " on " + them;
      continue;
    }
    const bool extra = has_mine && (!has_ref || mine[q].name < ref[q].name);
    const FieldEntry& e = extra ? mine[q] : ref[q];
    return "field " + field_name(e.name) + " (" + dtype_text(e.dtype) + ") is published on " + (extra ? who : them) +
           " but not on " + (extra ? them : who);
  }
  return {};
}

/// Collective: rank r's and ref_rank's field lists travel (bounded) and are compared.
std::string fields_difference(ParallelContext& ctx, const PublicationView& view, int r, int ref_rank) {
  std::string mine, ref;
  if (ctx.rank() == r || ctx.rank() == ref_rank) {
    const auto list = field_list(view.mesh, view.domains, view.ndomains);
    const std::string bytes = list ? serialised(*list, kMaxFieldListBytes) : std::string();
    (ctx.rank() == r ? mine : ref) = bytes;
  }
  ctx.broadcast(ref, ref_rank);
  ctx.broadcast(mine, r);
  std::string diff = list_difference(parsed(mine), parsed(ref), r, ref_rank);
  if (diff.empty())
    diff = "the field lists of " + rank_name(r) + " and " + rank_name(ref_rank) + " agree in their first " +
           std::to_string(kMaxFieldListBytes) + " bytes and differ after";
  return diff;
}

// ---------------------------------------------------------------------------------------
// Coordinates: chunk hashes, then the first differing chunk's values

std::string coords_difference(ParallelContext& ctx, const PublicationView& view, int a, std::int64_t count, int r) {
  const std::int64_t chunk = std::max(kMinChunk, (count + kMaxChunks - 1) / kMaxChunks);
  const std::int64_t chunks = (count + chunk - 1) / chunk;
  const bool holder = ctx.rank() == r || ctx.rank() == 0;
  const double* c = holder && view.mesh ? view.mesh->coords[a] : nullptr;
  const auto bytes_of = [&](std::int64_t k) {
    const std::int64_t n = std::min(chunk, count - k * chunk);
    return std::string_view(reinterpret_cast<const char*>(c + k * chunk), static_cast<std::size_t>(n) * sizeof(double));
  };
  // Which chunk differs first
  std::string hashes;
  if (c)
    for (std::int64_t k = 0; k < chunks; ++k) {
      const std::uint64_t h = fnv1a64(bytes_of(k));
      hashes.append(reinterpret_cast<const char*>(&h), sizeof h);
    }
  std::string mine = ctx.rank() == r ? hashes : std::string(), ref = ctx.rank() == 0 ? hashes : std::string();
  ctx.broadcast(ref, 0);
  ctx.broadcast(mine, r);
  std::int64_t first = 0;
  while (first < chunks && static_cast<std::size_t>(first + 1) * 8 <= std::min(mine.size(), ref.size()) &&
         std::memcmp(mine.data() + first * 8, ref.data() + first * 8, 8) == 0)
    ++first;
  if (first >= chunks) first = 0;  // hashes equal but the whole hash differed: compare the first chunk
  // Its values, then the first that differs bit for bit
  std::string vm = ctx.rank() == r && c ? std::string(bytes_of(first)) : std::string();
  std::string vr = ctx.rank() == 0 && c ? std::string(bytes_of(first)) : std::string();
  ctx.broadcast(vr, 0);
  ctx.broadcast(vm, r);
  const std::size_t n = std::min(vm.size(), vr.size()) / sizeof(double);
  for (std::size_t q = 0; q < n; ++q) {
    if (std::memcmp(vm.data() + q * 8, vr.data() + q * 8, 8) == 0) continue;
    double x, y;
    std::memcpy(&x, vm.data() + q * 8, 8);
    std::memcpy(&y, vr.data() + q * 8, 8);
    const std::int64_t index = first * chunk + static_cast<std::int64_t>(q);
    return indexed("coords", a) + "[" + std::to_string(index) + "] is " + format_number(x) + " on " + rank_name(r) +
           ", " + format_number(y) + " on rank 0 (a rectilinear axis' coordinates must be the same on every rank)";
  }
  return indexed("coords", a) + " differs between " + rank_name(r) + " and rank 0 (" + std::to_string(count) +
         " values)";
}

/// The C call a record's kind stands for.
const char* call_name(std::uint64_t kind) {
  return kind == 2 ? "tessera_execute_mesh_domains" : kind == 1 ? "tessera_execute_domains" : "tessera_execute";
}

// ---------------------------------------------------------------------------------------
// The fixed-size properties

/// The first property of grid or mesh that differs between rank r and rank 0 (bit for bit),
/// in words; "" if none differs. Needs the collective only for coordinates (`coords_axis`
/// set instead of a message).
std::string property_difference(const PublicationRecord& mine, const PublicationRecord& ref, int r, int& coords_axis) {
  const std::string who = rank_name(r);
  const bool mesh = ref.domains_call != 0;
  if (mesh && mine.association != ref.association)
    return who + "'s mesh has " + what_data(mine.association) + ", rank 0's " + what_data(ref.association);
  if (!std::equal(mine.global_dims, mine.global_dims + 3, ref.global_dims)) {
    int a = 0;
    while (mine.global_dims[a] == ref.global_dims[a]) ++a;
    return who + " has global_dims " + vec3(mine.global_dims) + ", rank 0 has " + vec3(ref.global_dims) + " (" +
           indexed("global_dims", a) + " differs)";
  }
  if (mesh && mine.nlevels != ref.nlevels)
    return who + "'s mesh has nlevels = " + std::to_string(mine.nlevels) + ", rank 0's " + std::to_string(ref.nlevels);
  for (std::int64_t l = 0; mesh && l + 1 < ref.nlevels; ++l)
    if (mine.refinement[l] != ref.refinement[l])
      return who + "'s mesh has refinement[" + std::to_string(l) + "] = " + std::to_string(mine.refinement[l]) +
             " (level " + std::to_string(l) + " -> " + std::to_string(l + 1) + "), rank 0's " +
             std::to_string(ref.refinement[l]);
  for (int a = 0; mesh && a < 3; ++a)
    if (((mine.axes_from_domains ^ ref.axes_from_domains) >> a) & 1) {
      const bool here = ((mine.axes_from_domains >> a) & 1) != 0;
      return axis_label(a) + " takes its coordinates from the domains' pieces (bit " + std::to_string(1 << a) +
             " of axes_from_domains) on " + (here ? who : "rank 0") + " but not on " + (here ? "rank 0" : who);
    }
  for (int a = 0; a < 3; ++a)
    if (mine.rectilinear[a] != ref.rectilinear[a]) {
      const bool rect = mine.rectilinear[a] != 0;
      const double h = std::bit_cast<double>(rect ? ref.spacing_bits[a] : mine.spacing_bits[a]);
      return axis_label(a) + " is rectilinear (" + indexed("coords", a) + " set) on " + (rect ? who : "rank 0") +
             " but uniform (spacing " + format_number(h) + ") on " + (rect ? "rank 0" : who);
    }
  const auto doubles = [](const std::uint64_t bits[3], double out[3]) {
    for (int a = 0; a < 3; ++a) out[a] = std::bit_cast<double>(bits[a]);
  };
  double x[3], y[3];
  for (const bool spacing : {true, false}) {
    const std::uint64_t* m = spacing ? mine.spacing_bits : mine.origin_bits;
    const std::uint64_t* f = spacing ? ref.spacing_bits : ref.origin_bits;
    if (std::equal(m, m + 3, f)) continue;
    int a = 0;
    while (m[a] == f[a]) ++a;
    doubles(m, x);
    doubles(f, y);
    return who + " has " + (spacing ? "spacing " : "origin ") + vec3(x) + ", rank 0 has " + vec3(y) + " (" +
           indexed(spacing ? "spacing" : "origin", a) + " differs)";
  }
  for (int a = 0; a < 3; ++a)
    if (mine.rectilinear[a] && !std::equal(mine.coords_hash[a], mine.coords_hash[a] + 2, ref.coords_hash[a])) {
      coords_axis = a;
      return {};
    }
  return {};
}

}  // namespace

PublicationRecord mesh_call_record() {
  PublicationRecord rec{};
  rec.domains_call = 2;
  return rec;
}

PublicationRecord publication_record(bool domains_call, const tessera_grid* grid, const tessera_mesh* mesh,
                                     const tessera_domain* domains, std::int64_t ndomains) {
  PublicationRecord rec{};
  rec.domains_call = domains_call ? 1 : 0;
  if (!domains_call) {
    if (grid) {
      rec.has_grid = 1;
      for (int a = 0; a < 3; ++a) {
        rec.origin_bits[a] = std::bit_cast<std::uint64_t>(grid->origin[a]);
        rec.spacing_bits[a] = std::bit_cast<std::uint64_t>(grid->spacing[a]);
        rec.global_dims[a] = grid->global_dims[a];
      }
    }
    return rec;
  }
  // A mesh that fails its own checks is reported by the bind phase, on every rank alike
  if (mesh_valid(mesh)) {
    rec.has_grid = 1;
    rec.association = mesh->association == TESSERA_CELL ? TESSERA_CELL : TESSERA_VERTEX;
    rec.nlevels = mesh->nlevels;
    rec.axes_from_domains = mesh->axes_from_domains;
    for (int l = 0; l + 1 < mesh->nlevels; ++l) rec.refinement[l] = mesh->refinement[l];
    for (int a = 0; a < 3; ++a) {
      const double* c = mesh->coords[a];
      rec.global_dims[a] = mesh->global_dims[a];
      rec.rectilinear[a] = c ? 1 : 0;
      // A rectilinear axis (or one in pieces): its spacing and origin are not read (0 here)
      const bool pieces = ((mesh->axes_from_domains >> a) & 1) != 0;
      rec.origin_bits[a] = c || pieces ? 0 : std::bit_cast<std::uint64_t>(mesh->origin[a]);
      rec.spacing_bits[a] = c || pieces ? 0 : std::bit_cast<std::uint64_t>(mesh->spacing[a]);
      if (c) {
        const std::string_view bytes(reinterpret_cast<const char*>(c),
                                     static_cast<std::size_t>(coord_count(*mesh, a)) * sizeof(double));
        rec.coords_hash[a][0] = fnv1a64(bytes);
        rec.coords_hash[a][1] = murmur64a(bytes);
      }
    }
  }
  if (const auto list = field_list(mesh, domains, ndomains)) {
    const std::string bytes = serialised(*list);
    rec.has_fields = 1;
    rec.fields_count = list->size();
    rec.fields_hash[0] = fnv1a64(bytes);
    rec.fields_hash[1] = murmur64a(bytes);
  }
  return rec;
}

std::optional<std::string> publication_disagreement(ParallelContext& ctx, std::int64_t step,
                                                    std::span<const PublicationRecord> all,
                                                    const PublicationView& mine) {
  const int n = static_cast<int>(all.size());
  if (n < 2) return std::nullopt;
  const PublicationRecord& ref = all[0];
  const std::string at = " at step " + std::to_string(step) + ": ";

  // Grid or mesh: a missing or invalid one fails the bind phase on every rank alike
  bool grids = true;
  for (const PublicationRecord& rec : all) grids = grids && rec.has_grid;
  for (int r = 1; r < n; ++r)
    if (all[r].domains_call != ref.domains_call)
      return std::string(ref.domains_call ? "ranks disagree on the mesh" : "ranks disagree on the grid") + at +
             rank_name(r) + " calls " + call_name(all[r].domains_call) + ", rank 0 " + call_name(ref.domains_call);
  if (grids)
    for (int r = 1; r < n; ++r) {
      int coords_axis = -1;
      std::string diff = property_difference(all[r], ref, r, coords_axis);
      if (diff.empty() && coords_axis >= 0) {
        const std::int64_t count = ref.global_dims[coords_axis] + (ref.association == TESSERA_CELL ? 1 : 0);
        diff = coords_difference(ctx, mine, coords_axis, count, r);
      }
      if (!diff.empty())
        return std::string(ref.domains_call ? "ranks disagree on the mesh" : "ranks disagree on the grid") + at + diff;
    }

  // Field lists (domains calls): every rank with domains against the first such rank
  int first = -1;
  for (int r = 0; r < n && first < 0; ++r)
    if (all[r].has_fields) first = r;
  for (int r = first + 1; first >= 0 && r < n; ++r) {
    if (!all[r].has_fields) continue;
    const PublicationRecord& a = all[r];
    const PublicationRecord& b = all[first];
    if (a.fields_count == b.fields_count && a.fields_hash[0] == b.fields_hash[0] &&
        a.fields_hash[1] == b.fields_hash[1])
      continue;
    return "ranks disagree on the published fields" + at + fields_difference(ctx, mine, r, first) +
           " (every domain of every rank must publish the same fields: the same names with the same dtypes)";
  }
  return std::nullopt;
}

}  // namespace tessera::insitu
