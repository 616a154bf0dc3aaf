// The path tracer of render.c in C++ over the same C API, with thin RAII
// wrappers (a handle freed once, an error thrown with Strata's message):
// the same image, bit for bit (both print its FNV-1a hash).
//
// usage: render_cpp OUT.ppm
//        render_cpp --golden-week09-sobol   (prints a golden row's hash)
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "strata.h"

namespace strata {

// Throws Strata's message when a call fails.
inline void check(StrataStatus s, const char *what) {
  if (s != STRATA_STATUS_OK) throw std::runtime_error(std::string(what) + ": " + strata_last_error());
}

struct SamplerFree {
  void operator()(StrataSampler *s) const { strata_sampler_free(s); }
};
struct BvhFree {
  void operator()(StrataBvh *b) const { strata_bvh_free(b); }
};
struct AlignedFree {
  void operator()(void *p) const { std::free(p); }
};

// A sampler that frees itself.
class Sampler {
 public:
  Sampler(StrataSamplerKind kind, uint32_t spp, uint64_t seed, uint32_t width, uint32_t height) {
    StrataSampler *s = nullptr;
    check(strata_sampler_new(kind, spp, seed, width, height, &s), "sampler");
    handle_.reset(s);
  }
  // Rows of `dims` values for the pixel samples given.
  std::vector<float> fill(const std::vector<uint32_t> &pixels, const std::vector<uint32_t> &indices,
                          uint32_t dims) {
    std::vector<float> out(indices.size() * dims);
    check(strata_sampler_fill(handle_.get(), pixels.data(), pixels.size(), indices.data(), indices.size(), dims,
                              out.data(), out.size()),
          "fill");
    return out;
  }

 private:
  std::unique_ptr<StrataSampler, SamplerFree> handle_;
};

// A sphere BVH and the aligned storage it lives in, freed together (the
// handle first).
class SphereBvh {
 public:
  explicit SphereBvh(const std::vector<float> &spheres) {
    size_t bytes = 0;
    check(strata_bvh_storage_size(spheres.size() / 4, &bytes), "storage size");
    storage_.reset(std::aligned_alloc(64, (bytes + 63) / 64 * 64));
    if (!storage_) throw std::bad_alloc();
    StrataBvh *b = nullptr;
    check(strata_bvh_build(spheres.data(), spheres.size(), storage_.get(), bytes, &b), "build");
    handle_.reset(b);
  }
  void closest(const std::vector<StrataRay> &rays, size_t n, std::vector<StrataHit> &hits) const {
    check(strata_bvh_closest_hit(handle_.get(), rays.data(), n, hits.data(), hits.size()), "closest hit");
  }

 private:
  std::unique_ptr<void, AlignedFree> storage_;  // declared first: freed last
  std::unique_ptr<StrataBvh, BvhFree> handle_;
};

}  // namespace strata

namespace {

constexpr int W = 64, H = 36, SPP = 16, DEPTH = 4, DIMS = 2 + 2 * DEPTH, PATHS = W * H * SPP;

const std::vector<float> SPHERES = {0.0f, -100.5f, -1.0f, 100.0f, 0.0f, 0.0f, -1.2f, 0.5f,
                                    -1.0f, 0.0f,    -1.0f, 0.5f,   1.0f, 0.0f, -1.0f, 0.5f};

int run(const char *path) {
  std::vector<uint32_t> pixels(2 * PATHS), index(PATHS);
  for (size_t i = 0; i < PATHS; i++) {
    size_t p = i / SPP;
    pixels[2 * i] = static_cast<uint32_t>(p % W);
    pixels[2 * i + 1] = static_cast<uint32_t>(p / W);
    index[i] = static_cast<uint32_t>(i % SPP);
  }
  const std::vector<float> u =
      strata::Sampler(STRATA_SAMPLER_KIND_SOBOL, SPP, 7, W, H).fill(pixels, index, DIMS);
  const strata::SphereBvh bvh(SPHERES);

  std::vector<StrataRay> rays(PATHS);
  std::vector<StrataHit> hits(PATHS);
  std::vector<uint32_t> live(PATHS);
  std::vector<float> throughput(3 * PATHS, 1.0f), radiance(3 * PATHS, 0.0f);
  std::vector<float> normals(3 * PATHS), local(3 * PATHS), world(3 * PATHS), u2(2 * PATHS);
  for (size_t i = 0; i < PATHS; i++) {
    float x = (static_cast<float>(pixels[2 * i]) + u[i * DIMS]) / static_cast<float>(H) * 2.0f -
              static_cast<float>(W) / static_cast<float>(H);
    float y = 1.0f - (static_cast<float>(pixels[2 * i + 1]) + u[i * DIMS + 1]) / static_cast<float>(H) * 2.0f;
    float inv = 1.0f / std::sqrt(x * x + y * y + 1.0f);
    rays[i] = StrataRay{{0.0f, 0.0f, 0.0f}, {x * inv, y * inv, -inv}, 0.0f, INFINITY};
    live[i] = static_cast<uint32_t>(i);
  }

  size_t n_live = PATHS;
  for (int bounce = 0; bounce < DEPTH && n_live > 0; bounce++) {
    size_t next = 0;
    bvh.closest(rays, n_live, hits);
    for (size_t i = 0; i < n_live; i++) {
      const uint32_t p = live[i];
      StrataRay &r = rays[i];
      if (hits[i].id == UINT32_MAX) {
        float t = 0.5f * (r.dir[1] + 1.0f);
        const float sky[3] = {1.0f - 0.5f * t, 1.0f - 0.3f * t, 1.0f};
        for (int k = 0; k < 3; k++) radiance[3 * p + k] += throughput[3 * p + k] * sky[k];
        continue;
      }
      const float *s = &SPHERES[4 * hits[i].id];
      float n[3];
      for (int k = 0; k < 3; k++) n[k] = (r.origin[k] + hits[i].t * r.dir[k] - s[k]) / s[3];
      float inv = 1.0f / std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      for (int k = 0; k < 3; k++) {
        normals[3 * next + k] = n[k] * inv;
        rays[next].origin[k] = r.origin[k] + hits[i].t * r.dir[k];
        throughput[3 * p + k] *= 0.5f;
      }
      u2[2 * next] = u[static_cast<size_t>(p) * DIMS + 2 + 2 * bounce];
      u2[2 * next + 1] = u[static_cast<size_t>(p) * DIMS + 3 + 2 * bounce];
      live[next++] = p;
    }
    n_live = next;
    strata::check(strata_mapping_sample(STRATA_MAPPING_COSINE_HEMISPHERE, 0.0f, u2.data(), 2 * n_live,
                                        local.data(), 3 * n_live),
                  "directions");
    strata::check(strata_onb_to_world(STRATA_ONB_DUFF, normals.data(), 3 * n_live, local.data(), 3 * n_live,
                                      world.data(), 3 * n_live),
                  "to world");
    for (size_t i = 0; i < n_live; i++) {
      const float *d = &world[3 * i];
      float inv = 1.0f / std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (int k = 0; k < 3; k++) rays[i].dir[k] = d[k] * inv;
      rays[i].t_min = 1e-3f;
      rays[i].t_max = INFINITY;
    }
  }

  std::vector<float> image(3 * W * H);
  for (size_t i = 0; i < static_cast<size_t>(W) * H; i++)
    for (int k = 0; k < 3; k++) {
      float sum = 0.0f;
      for (int s = 0; s < SPP; s++) sum += radiance[3 * (i * SPP + s) + k];
      image[3 * i + k] = sum / static_cast<float>(SPP);
    }
  uint64_t hash = 0xcbf29ce484222325ull;
  for (float v : image) {
    uint32_t w;
    std::memcpy(&w, &v, 4);
    for (int k = 0; k < 4; k++) hash = (hash ^ ((w >> (8 * k)) & 0xff)) * 0x100000001b3ull;
  }
  std::unique_ptr<FILE, int (*)(FILE *)> out(std::fopen(path, "wb"), std::fclose);
  if (!out) throw std::runtime_error(std::string("cannot write ") + path);
  std::fprintf(out.get(), "P6\n%d %d\n255\n", W, H);
  for (float v : image) {
    float g = std::sqrt(v);
    std::fputc(static_cast<int>(255.0f * (g < 1.0f ? g : 1.0f) + 0.5f), out.get());
  }
  std::printf("%016llx\n", static_cast<unsigned long long>(hash));
  return 0;
}

}  // namespace

// Strata's own renderer from C++: the golden render of week09 with the
// Sobol' sampler (the flags of std-runner/tests/data/golden.json), its
// film hash printed for the test to compare with the golden row.
uint64_t golden_week09() {
  const char *flags[] = {"--scene", "week09", "--sampler", "sobol", "--width", "32", "--height", "18",
                         "--spp",   "4",      "--seed",    "5",     "--max-depth", "8"};
  StrataRender *raw = nullptr;
  strata::check(strata_render_new(flags, sizeof flags / sizeof flags[0], &raw), "render");
  std::unique_ptr<StrataRender, void (*)(StrataRender *)> render(raw, strata_render_free);
  StrataRenderInfo info{};
  strata::check(strata_render_info(render.get(), &info), "info");
  std::vector<StrataPixelSum> film(static_cast<size_t>(info.film_width) * info.film_height);
  strata::check(strata_render_film(render.get(), 2, film.data(), film.size()), "film");
  uint64_t hash = 0;
  strata::check(strata_film_hash(film.data(), film.size(), &hash), "hash");
  return hash;
}

int main(int argc, char **argv) {
  if (argc == 2 && std::strcmp(argv[1], "--golden-week09-sobol") == 0) {
    try {
      std::printf("%016llx\n", static_cast<unsigned long long>(golden_week09()));
      return 0;
    } catch (const std::exception &e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 1;
    }
  }
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.ppm | --golden-week09-sobol\n", argv[0]);
    return 2;
  }
  try {
    return run(argv[1]);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
