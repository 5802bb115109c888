/// DeviceScene (device_scene.h): plans, allocates and fills the device copies of a prepared
/// scene's KernelScene.
#include "cuda/device_scene.h"

#include <tessera/byte_span.h>

#include "cuda/device_mesh_tables.h"
#include "cuda/device_value_dispatch.h"
#include "cuda/pixel_kernel.h"
#include "mesh/mesh_layout.h"
#include "scene/prepared_scene_impl.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>

namespace tessera::cuda {

namespace {
/// Alignment of each table in the allocation (cudaMalloc's own)
constexpr std::size_t kAlign = 256;
}  // namespace

std::size_t DeviceScene::reserve(std::size_t bytes) {
  const std::size_t off = (m_size + kAlign - 1) / kAlign * kAlign;
  m_size = off + std::max<std::size_t>(bytes, 1);
  return off;
}

std::size_t DeviceScene::plan_copy(const void* src, std::size_t bytes, const char* what) {
  const std::size_t off = reserve(bytes);
  if (bytes > 0) m_copies.push_back({src, bytes, off, what});
  return off;
}

DeviceScene::DeviceScene(const PreparedSceneImpl& s, std::shared_ptr<DeviceBackend> backend, std::uint64_t budget)
    : m_scene(s), m_backend(std::move(backend)) {
  const KernelScene& ks = s.kernel;
  // A strided array: read in place when device or managed memory, else its span copied and
  // `set` given the copy's address of element (0, 0, 0)
  using Setter = void (*)(KernelScene&, int, const unsigned char*);
  const auto strided = [&](const void* data, const std::int64_t dims[3], const std::int64_t strides[3],
                           std::size_t elem, const char* what, Setter set, int index) {
    if (m_backend->memory_kind(data) != MemoryKind::Host) return true;
    const ByteSpan sp = byte_span(dims, strides, elem);
    const auto* p = static_cast<const unsigned char*>(data);
    const std::size_t off = plan_copy(p + sp.lo, static_cast<std::size_t>(sp.hi - sp.lo), what);
    const std::int64_t lo = sp.lo;
    m_fix.push_back([=](unsigned char* base, KernelScene& d) { set(d, index, base + off - lo); });
    return false;
  };

  // The field's values: a mesh's domains, one array, a vector's three components, or the
  // levels' patches
  if (ks.mesh.element != nullptr) {
    plan_mesh();
  } else if (ks.paged.cache != nullptr) {
    // A distributed field: the own block read on the device (the caller's device array, or a
    // copy of the host one); every other brick comes to the device's pool as the launches ask
    // (planned last, below, when the rest's size is known)
    if (ks.paged.local.data) {
      const void* dev = s.paged_local_device;
      if (dev && m_backend->memory_kind(dev) != MemoryKind::Host)
        m_fix.push_back([dev](unsigned char*, KernelScene& d) { d.paged.local.data = dev; });
      else
        strided(
            ks.paged.local.data, ks.paged.local.dims, ks.paged.local.byte_strides, dtype_size(ks.paged.dtype),
            "own block copy", [](KernelScene& d, int, const unsigned char* p) { d.paged.local.data = p; }, 0);
    } else if (s.paged_device_own.data && m_backend->memory_kind(s.paged_device_own.data) == MemoryKind::Host) {
      throw std::invalid_argument("paged field: the own block declared device memory only is host memory");
    }
  } else if (ks.amr.nlevels == 0 && !ks.magnitude.active()) {
    m_field_in_place = strided(
        ks.field.data, ks.field.dims, ks.field.byte_strides, dtype_size(ks.field.dtype), "field copy",
        [](KernelScene& d, int, const unsigned char* p) { d.field.data = p; }, 0);
  } else if (ks.magnitude.active()) {
    m_field_in_place = true;
    for (int c = 0; c < 3; ++c)
      m_field_in_place &= strided(
          ks.magnitude.base[c], ks.field.dims, ks.magnitude.s[c], dtype_size(ks.magnitude.dtype[c]),
          "vector component copy", [](KernelScene& d, int i, const unsigned char* p) { d.magnitude.base[i] = p; }, c);
  } else {
    // Refinement levels: each level's stencil table and candidate lists (their lengths read
    // from the table), the per-macrocell finest level, the patches and their values
    const AmrFieldView& amr = ks.amr;
    std::int64_t max_patch = -1;
    for (int l = 0; l < amr.nlevels; ++l) {
      const AmrLevelView& L = amr.level[l];
      const auto entries = static_cast<std::size_t>(L.cells[0] * L.cells[1] * L.cells[2]);
      std::int64_t lists = 0;  // candidate lists: entry e <= -2 is list -2 - e
      for (std::size_t e = 0; e < entries; ++e) {
        const std::int32_t v = L.table[e];
        if (v >= 0) max_patch = std::max<std::int64_t>(max_patch, v);
        else if (v <= -2) lists = std::max<std::int64_t>(lists, -1 - static_cast<std::int64_t>(v));
      }
      const std::size_t t_off = plan_copy(L.table, entries * sizeof(std::int32_t), "refinement level table");
      m_fix.push_back([=](unsigned char* base, KernelScene& d) {
        d.amr.level[l].table = reinterpret_cast<const std::int32_t*>(base + t_off);
      });
      if (lists > 0) {
        const auto ncand = static_cast<std::size_t>(L.first[lists]);
        for (std::size_t m = 0; m < ncand; ++m) max_patch = std::max<std::int64_t>(max_patch, L.cand[m]);
        const std::size_t f_off =
            plan_copy(L.first, static_cast<std::size_t>(lists + 1) * sizeof(std::uint32_t), "refinement candidates");
        const std::size_t c_off = plan_copy(L.cand, ncand * sizeof(std::int32_t), "refinement candidates");
        m_fix.push_back([=](unsigned char* base, KernelScene& d) {
          d.amr.level[l].first = reinterpret_cast<const std::uint32_t*>(base + f_off);
          d.amr.level[l].cand = reinterpret_cast<const std::int32_t*>(base + c_off);
        });
      }
    }
    const std::size_t fin_off =
        plan_copy(amr.finest, static_cast<std::size_t>(amr.nc[0] * amr.nc[1] * amr.nc[2]), "finest levels");
    m_fix.push_back([=](unsigned char* base, KernelScene& d) { d.amr.finest = base + fin_off; });
    m_npatches = static_cast<std::size_t>(max_patch + 1);
    m_off_patches = reserve(m_npatches * sizeof(AmrPatchAddress));
    m_field_in_place = true;
    for (std::size_t i = 0; i < m_npatches; ++i) {
      const AmrPatchAddress& P = amr.patch[i];
      std::int64_t dims[3];
      for (int a = 0; a < 3; ++a) dims[a] = std::max<std::int64_t>(P.hi[a] - P.lo[a], 1);
      const ByteSpan sp = byte_span(dims, P.s, dtype_size(amr.dtype));
      const unsigned char* first = P.at(P.lo[0], P.lo[1], P.lo[2]);
      if (m_backend->memory_kind(first) != MemoryKind::Host) {
        m_patch_data.emplace_back(SIZE_MAX, 0);
        continue;
      }
      m_field_in_place = false;
      const std::size_t off = plan_copy(first + sp.lo, static_cast<std::size_t>(sp.hi - sp.lo), "patch copy");
      // the copy starts at byte (lo + sp.lo) from the patch's origin
      const std::ptrdiff_t start = (first + sp.lo) - reinterpret_cast<const unsigned char*>(P.origin);
      m_patch_data.emplace_back(off, start);
    }
  }

  // A plain float32 field: widened to a float64 copy on the device (widen_field.h says why)
  m_dispatch = std::make_shared<KernelScene>(ks);
  if (ks.mesh.element == nullptr && ks.amr.nlevels == 0 && !ks.magnitude.active() && ks.paged.cache == nullptr &&
      ks.field.dtype == DType::Float32 && !kFloat32Kernel) {
    const auto n = static_cast<std::size_t>(ks.field.dims[0] * ks.field.dims[1] * ks.field.dims[2]);
    m_off_widened = reserve(n * sizeof(double));
    m_dispatch->field.dtype = DType::Float64;
  }

  // Majorants and empty-space reach, one per macrocell; the transfer function
  const auto cells = static_cast<std::size_t>(ks.cells[0] * ks.cells[1] * ks.cells[2]);
  const std::size_t maj_off = plan_copy(ks.majorant, cells * sizeof(double), "majorants");
  m_fix.push_back(
      [=](unsigned char* base, KernelScene& d) { d.majorant = reinterpret_cast<const double*>(base + maj_off); });
  if (ks.empty_reach) {
    const std::size_t er_off = plan_copy(ks.empty_reach, cells, "empty-space reach");
    m_fix.push_back([=](unsigned char* base, KernelScene& d) { d.empty_reach = base + er_off; });
  }
  const std::size_t tf_off = plan_copy(ks.tf, sizeof(TransferFunction), "transfer function");
  m_fix.push_back(
      [=](unsigned char* base, KernelScene& d) { d.tf = reinterpret_cast<const TransferFunction*>(base + tf_off); });

  // Rectilinear axes: the caller's coordinates (in place when on the device), bins, walls
  for (int a = 0; a < 3; ++a) {
    const AxisMap& m = ks.axis[a];
    if (!m.coords) continue;
    if (m_backend->memory_kind(m.coords) == MemoryKind::Host) {
      const auto n = static_cast<std::size_t>(m.n + (m.cell ? 1 : 0));
      const std::size_t off = plan_copy(m.coords, n * sizeof(double), "axis coordinates");
      m_fix.push_back(
          [=](unsigned char* base, KernelScene& d) { d.axis[a].coords = reinterpret_cast<const double*>(base + off); });
    }
    const std::size_t b_off =
        plan_copy(m.bins, static_cast<std::size_t>(m.nbins + 1) * sizeof(std::int64_t), "axis bins");
    const std::size_t w_off =
        plan_copy(m.walls, static_cast<std::size_t>(ks.cells[a] + 1) * sizeof(double), "axis walls");
    m_fix.push_back([=](unsigned char* base, KernelScene& d) {
      d.axis[a].bins = reinterpret_cast<const std::int64_t*>(base + b_off);
      d.axis[a].walls = reinterpret_cast<const double*>(base + w_off);
    });
  }

  // An envmap's texels and sampling table (the other backgrounds have none)
  const std::span<const Color> texels = s.env.texels();
  const std::span<const double> table = s.env.distribution_table();
  if (!texels.empty()) {
    m_off_texels = plan_copy(texels.data(), texels.size_bytes(), "envmap texels");
    m_off_env_table = plan_copy(table.data(), table.size_bytes(), "envmap sampling table");
  }

  // The background, the lights, the KernelScene and the medium: written by upload()
  m_off_env = reserve(sizeof(Environment));
  m_off_lights = reserve(static_cast<std::size_t>(ks.lights.count()) * sizeof(Light));
  m_off_kernel = reserve(sizeof(KernelScene));
  m_medium_bytes = device_medium_bytes(*m_dispatch);
  m_off_medium = reserve(m_medium_bytes);

  if (ks.paged.cache != nullptr) {
    // The brick pool: the host cache's slots and the bricks of the rank's other own blocks
    // (BrickCache::set_in_place: the device reads those through the pool too), within the
    // budget beside the rest (256 bytes of alignment slack), at least one. A launch has at
    // most a thread per pixel and lane (sample_lanes)
    m_brick_threads = static_cast<std::uint64_t>(ks.width) * static_cast<std::uint64_t>(ks.height) *
                      static_cast<std::uint64_t>(sample_lanes(ks.width, ks.height, ks.spp));
    const BrickGrid g = DeviceBricks::grid_of(ks.paged);
    const auto bricks = static_cast<std::uint64_t>(g.brick_count());
    const auto edge3 = static_cast<std::uint64_t>(g.edge() * g.edge() * g.edge());
    const std::uint64_t own =
        (ks.paged.cache->in_place_vertices() + edge3 - 1) / edge3 + ks.paged.cache->in_place_count();
    std::size_t cap = static_cast<std::size_t>(
        std::min<std::uint64_t>(static_cast<std::uint64_t>(ks.paged.cache->capacity()) + own, bricks));
    if (budget > 0)
      cap = std::min(cap, DeviceBricks::capacity_for(ks.paged, budget > m_size + 256 ? budget - m_size - 256 : 0,
                                                     m_brick_threads));
    m_brick_capacity = std::max<std::size_t>(cap, 1);
    m_off_bricks = reserve(DeviceBricks::bytes_for(ks.paged, m_brick_capacity, m_brick_threads));
    m_field_in_place = false;
  }
}

// The device's mesh slots are MeshArraySlot's first five (a ghost mask is read on the host only)
static_assert(static_cast<int>(MeshArraySlot::Field) == 4 && static_cast<int>(MeshArraySlot::Ghosts) == 5);

void DeviceScene::plan_mesh() {
  const MeshTables& t = m_scene.mesh;
  m_mesh_layout = t.layout().get();
  m_off_domains = reserve(t.domains().size() * sizeof(DomainAccess));
  const std::size_t d_off = m_off_domains;
  m_fix.push_back([=](unsigned char* base, KernelScene& d) {
    d.mesh.domain = reinterpret_cast<const DomainAccess*>(base + d_off);
  });
  // Each domain's arrays (x, y, z, connectivity, values): read in place where they are device
  // or managed memory, or where the caller names a device copy of them. The others are copied:
  // the geometry's (x, y, z, connectivity) into the copy kept with the layout (with its
  // tables: device_mesh_tables.h), which later renders over the same layout and arrays read
  // where it is; the values into this scene's allocation. Spans that overlap or touch
  // (interleaved x, y, z) make one copy
  const auto host = [&](const void* p) { return m_backend->memory_kind(p) == MemoryKind::Host; };
  m_field_in_place = true;
  const std::span<const DomainAccess> readers = t.domains();
  for (std::size_t i = 0; i < readers.size(); ++i) {
    const MeshTables::DomainArrays& arrays = t.arrays()[i];
    MeshArrays m;
    std::vector<AddressSpan> geometry;
    for (int k = 0; k < kMeshSlots; ++k) {
      const MeshArraySpan& a = arrays.span[static_cast<std::size_t>(k)];
      const void* named = arrays.device_copy[static_cast<std::size_t>(k)];
      if (!a.data) continue;
      if (named && !host(named)) {
        m.in_place[k] = static_cast<const unsigned char*>(named);
        continue;
      }
      if (!host(a.data)) continue;  // device or managed memory: read where it is
      const auto* p = static_cast<const unsigned char*>(a.data);
      if (k < MeshGeometryCopies::kSlots) {
        geometry.push_back({p, p + a.bytes, k});
        continue;
      }
      m.off[k] = plan_copy(p, static_cast<std::size_t>(a.bytes), "mesh values");
      m.lo[k] = p;
    }
    if (!geometry.empty() || m.off[kMeshSlots - 1] != SIZE_MAX) m_field_in_place = false;
    m_mesh_geometry.add_domain(readers[i], geometry);
    m_mesh_arrays.push_back(m);
  }
  // Its size, and whether the layout keeps one on this device for these arrays (as planned:
  // one made meanwhile by another render is taken)
  m_mesh_table_bytes = DeviceMeshTables::bytes_of(*m_mesh_layout, m_mesh_geometry);
  m_mesh_tables_kept = DeviceMeshTables::kept(*m_mesh_layout, m_mesh_geometry, m_backend.get());
}

DeviceScene::~DeviceScene() { m_backend->release(m_base); }

std::uint64_t DeviceScene::upload() {
  const KernelScene& ks = m_scene.kernel;
  m_base = m_backend->allocate(m_size, "scene copies");
  auto* base = static_cast<unsigned char*>(m_base);
  std::uint64_t copied = 0;
  const auto put = [&](std::size_t off, const void* src, std::size_t bytes, const char* what) {
    if (bytes == 0) return;
    m_backend->copy_to_device(base + off, src, bytes, what);
    copied += bytes;
  };
  for (const Copy& c : m_copies) put(c.offset, c.src, c.bytes, c.what);

  // The KernelScene over the device copies
  KernelScene d = ks;
  for (const auto& fix : m_fix) fix(base, d);
  if (m_off_bricks != SIZE_MAX) {
    m_bricks =
        std::make_unique<DeviceBricks>(*m_backend, ks.paged, m_brick_capacity, m_brick_threads, base + m_off_bricks);
    copied += m_bricks->reset();
    d.paged = m_bricks->device_view(d.paged.local.data);
    if (const PreparedSceneImpl& s = m_scene;
        s.paged_device_own.data) {  // device memory only: read in place, never through the bricks
      d.paged.local = s.paged_device_own;
      for (int a = 0; a < 3; ++a) {
        d.paged.lo[a] = s.paged_device_lo[a];
        d.paged.hi[a] = s.paged_device_lo[a] + s.paged_device_own.dims[a];
      }
    }
  }
  if (m_off_widened != SIZE_MAX) {
    // The float32 values (copied above, or the caller's device memory) widened to float64
    auto* wide = reinterpret_cast<double*>(base + m_off_widened);
    m_backend->widen_float32(static_cast<const unsigned char*>(d.field.data), d.field.dims, d.field.byte_strides, wide);
    d.field.data = wide;
    d.field.dtype = DType::Float64;
    d.field.byte_strides[0] = sizeof(double);
    d.field.byte_strides[1] = d.field.byte_strides[0] * d.field.dims[0];
    d.field.byte_strides[2] = d.field.byte_strides[1] * d.field.dims[1];
  }
  if (m_npatches > 0) {
    std::vector<AmrPatchAddress> patches(ks.amr.patch, ks.amr.patch + m_npatches);
    for (std::size_t i = 0; i < m_npatches; ++i) {
      const auto [off, start] = m_patch_data[i];
      if (off == SIZE_MAX) continue;  // device memory: in place
      patches[i].origin = reinterpret_cast<std::intptr_t>(base + off) - start;
    }
    put(m_off_patches, patches.data(), patches.size() * sizeof(AmrPatchAddress), "patch addresses");
    d.amr.patch = reinterpret_cast<const AmrPatchAddress*>(base + m_off_patches);
  }
  if (m_mesh_layout) {
    m_mesh_tables = DeviceMeshTables::of(*m_mesh_layout, m_mesh_geometry, m_backend, &copied);
    d.mesh.element = m_mesh_tables->element;
    d.mesh.box = m_mesh_tables->box;
    d.mesh.first = m_mesh_tables->first;
    d.mesh.list = m_mesh_tables->list;
  }
  if (!m_mesh_arrays.empty()) {
    // A mesh's domain readers over the copies of their arrays
    const std::span<const DomainAccess> host_domains = m_scene.mesh.domains();
    std::vector<DomainAccess> domains(host_domains.begin(), host_domains.end());
    for (std::size_t i = 0; i < domains.size(); ++i) {
      DomainAccess& a = domains[i];
      const MeshArrays& m = m_mesh_arrays[i];
      const std::array<MeshGeometryCopies::Slot, MeshGeometryCopies::kSlots>& kept = m_mesh_geometry.slots()[i];
      const unsigned char** ptr[kMeshSlots] = {&a.x, &a.y, &a.z, &a.conn, &a.values};
      for (int k = 0; k < kMeshSlots; ++k) {
        if (m.in_place[k]) *ptr[k] = m.in_place[k];
        else if (m.off[k] != SIZE_MAX) *ptr[k] = base + m.off[k] + (*ptr[k] - m.lo[k]);
        else if (k < MeshGeometryCopies::kSlots && kept[k].run >= 0)
          *ptr[k] = m_mesh_tables->run(static_cast<std::size_t>(kept[k].run)) + kept[k].offset;
      }
    }
    put(m_off_domains, domains.data(), domains.size() * sizeof(DomainAccess), "mesh domains");
  }
  // The background (an envmap's over the copies of its tables) and the lights, the
  // background light pointing at the device's copy
  const Environment env = m_scene.env.relocated(reinterpret_cast<const Color*>(base + m_off_texels),
                                                reinterpret_cast<const double*>(base + m_off_env_table));
  put(m_off_env, &env, sizeof(Environment), "background");
  const auto* env_dev = reinterpret_cast<const Environment*>(base + m_off_env);
  std::vector<Light> host_lights;
  for (int i = 0; i < ks.lights.count(); ++i)
    host_lights.push_back(i < ks.lights.area_count() ? ks.lights[i] : Light(EnvironmentLight(env_dev)));
  put(m_off_lights, host_lights.data(), host_lights.size() * sizeof(Light), "lights");
  d.lights = ks.lights.relocated(reinterpret_cast<const Light*>(base + m_off_lights), env_dev);
  // No tile list on the device: the host hands it pixels
  d.tiles = nullptr;
  d.tile_culled = nullptr;
  d.tile_count = 0;
  put(m_off_kernel, &d, sizeof(KernelScene), "kernel scene");
  std::vector<unsigned char> m(m_medium_bytes);
  make_device_medium(d, m.data());
  put(m_off_medium, m.data(), m.size(), "medium");
  return copied;
}

const KernelScene* DeviceScene::kernel() const {
  return reinterpret_cast<const KernelScene*>(static_cast<unsigned char*>(m_base) + m_off_kernel);
}

const void* DeviceScene::medium() const { return static_cast<unsigned char*>(m_base) + m_off_medium; }

}  // namespace tessera::cuda
