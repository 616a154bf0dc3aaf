/* The C API against the core's value locks (core/tests/data/locks.json),
 * bit for bit, and against bad input: every call with a null pointer, a
 * short buffer, an unknown kind or an out-of-range value returns its
 * error code and a message, never a crash.
 *
 * usage: locks LOCKS_JSON GOLDEN_JSON EXPECTED_SIMD_LEVEL
 * (the reference sphere lists are read beside LOCKS_JSON)
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "strata.h"

static int failures = 0;

#define CHECK(cond, ...)                                                   \
  do {                                                                     \
    if (!(cond)) {                                                         \
      fprintf(stderr, "FAIL %s:%d: ", __FILE__, __LINE__);                 \
      fprintf(stderr, __VA_ARGS__);                                        \
      fprintf(stderr, "\n");                                               \
      failures++;                                                          \
    }                                                                      \
  } while (0)

/* ---------------------------------------------------------- the data file */

static char *read_file(const char *path) {
  FILE *f = fopen(path, "rb");
  long n;
  char *text;
  if (!f) return NULL;
  if (fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
    fclose(f);
    return NULL;
  }
  text = malloc((size_t)n + 1);
  if (text && fread(text, 1, (size_t)n, f) != (size_t)n) {
    free(text);
    text = NULL;
  }
  if (text) text[n] = '\0';
  fclose(f);
  return text;
}

/* The text after `"key":` in the file (keys are unique in it). */
static const char *after_key(const char *json, const char *key) {
  char quoted[128];
  const char *at;
  snprintf(quoted, sizeof quoted, "\"%s\":", key);
  at = strstr(json, quoted);
  return at ? at + strlen(quoted) : NULL;
}

/* `n` unsigned numbers of the array at `key`. */
static int read_u32s(const char *json, const char *key, uint32_t *out, int n) {
  const char *p = after_key(json, key);
  int i;
  if (!p || !(p = strchr(p, '['))) return 0;
  p++;
  for (i = 0; i < n; i++) {
    char *end;
    unsigned long v = strtoul(p, &end, 10);
    if (end == p) return 0;
    out[i] = (uint32_t)v;
    p = end;
    while (*p == ',' || *p == ' ') p++;
  }
  return 1;
}

/* The hexadecimal string at `key`. */
static int read_hex(const char *json, const char *key, uint64_t *out) {
  const char *p = after_key(json, key);
  if (!p || !(p = strchr(p, '"'))) return 0;
  *out = strtoull(p + 1, NULL, 16);
  return 1;
}

/* ---------------------------------------------------------- bits */

static uint32_t bits(float f) {
  uint32_t u;
  memcpy(&u, &f, sizeof u);
  return u;
}

/* FNV-1a over 32-bit words, little-endian bytes: the locks' hash. */
typedef struct {
  uint64_t h;
} Fnv;

static void fnv_word(Fnv *f, uint32_t w) {
  int k;
  for (k = 0; k < 4; k++) {
    f->h ^= (w >> (8 * k)) & 0xff;
    f->h *= 0x100000001b3ull;
  }
}

static void fnv_floats(Fnv *f, const float *v, size_t n) {
  size_t i;
  for (i = 0; i < n; i++) fnv_word(f, bits(v[i]));
}

/* ---------------------------------------------------------- samplers */

static void sampler_locks(const char *json) {
  struct {
    const char *name;
    uint32_t kind, spp, width, height;
  } cases[] = {
      {"independent", STRATA_SAMPLER_KIND_INDEPENDENT, 16, 0, 0},
      {"grid", STRATA_SAMPLER_KIND_GRID, 16, 0, 0},
      {"stratified", STRATA_SAMPLER_KIND_STRATIFIED, 16, 0, 0},
      {"sobol", STRATA_SAMPLER_KIND_SOBOL, 16, 0, 0},
      {"halton", STRATA_SAMPLER_KIND_HALTON, 16, 0, 0},
      {"zsobol", STRATA_SAMPLER_KIND_ZSOBOL, 16, 320, 180},
      {"zsobol_wide", STRATA_SAMPLER_KIND_ZSOBOL, 256, 1u << 20, 1u << 20},
  };
  size_t c;
  for (c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    StrataSampler *s = NULL;
    uint32_t want[5], got[5], spp = 0;
    float p[2], a, b[2];
    int k;
    CHECK(read_u32s(json, cases[c].name, want, 5), "%s: not in the locks file", cases[c].name);
    CHECK(strata_sampler_new(cases[c].kind, cases[c].spp, 2026, cases[c].width, cases[c].height, &s) ==
              STRATA_STATUS_OK,
          "%s: %s", cases[c].name, strata_last_error());
    if (!s) continue;
    CHECK(strata_sampler_spp(s, &spp) == STRATA_STATUS_OK && spp == cases[c].spp, "%s: spp", cases[c].name);
    /* The lock's order: position, one 1-D, one 2-D. */
    strata_sampler_start(s, 12, 34, 5);
    strata_sampler_pixel_2d(s, p, 2);
    strata_sampler_next_1d(s, &a, 1);
    strata_sampler_next_2d(s, b, 2);
    got[0] = bits(p[0]);
    got[1] = bits(p[1]);
    got[2] = bits(a);
    got[3] = bits(b[0]);
    got[4] = bits(b[1]);
    for (k = 0; k < 5; k++)
      CHECK(got[k] == want[k], "%s value %d: %08x, locked %08x", cases[c].name, k, got[k], want[k]);
    {
      /* A batch equals the single calls: rows of 7 (position, two 2-D,
       * one 1-D) for 3 pixel samples. */
      uint32_t pixels[6] = {12, 34, 0, 0, 319, 179};
      uint32_t indices[3] = {5, 0, 15};
      float rows[21], one[7];
      int i;
      CHECK(strata_sampler_fill(s, pixels, 6, indices, 3, 7, rows, 21) == STRATA_STATUS_OK, "%s fill: %s",
            cases[c].name, strata_last_error());
      for (i = 0; i < 3; i++) {
        strata_sampler_start(s, pixels[2 * i], pixels[2 * i + 1], indices[i]);
        strata_sampler_pixel_2d(s, one, 2);
        strata_sampler_next_2d(s, one + 2, 2);
        strata_sampler_next_2d(s, one + 4, 2);
        strata_sampler_next_1d(s, one + 6, 1);
        for (k = 0; k < 7; k++)
          CHECK(bits(rows[7 * i + k]) == bits(one[k]), "%s fill row %d dim %d", cases[c].name, i, k);
      }
    }
    strata_sampler_free(s);
  }
}

/* ---------------------------------------------------------- mappings */

#define GRID 97

/* The locks' 97 x 97 grid over [0, 1)^2, edges included: t(96) is the
 * largest float below 1. */
static void grid(float *u) {
  int i, j;
  for (i = 0; i < GRID; i++)
    for (j = 0; j < GRID; j++) {
      u[2 * (i * GRID + j)] = i == GRID - 1 ? 0x1.fffffep-1f : (float)i / 96.0f;
      u[2 * (i * GRID + j) + 1] = j == GRID - 1 ? 0x1.fffffep-1f : (float)j / 96.0f;
    }
}

enum { N = GRID * GRID };

static float u2[2 * N], u3[3 * N], pts[3 * N], back[3 * N], pdf[N], pts2[3 * N], back2[3 * N];

static void ok(StrataStatus s, const char *what) {
  CHECK(s == STRATA_STATUS_OK, "%s: %s", what, strata_last_error());
}

/* sample, then invert and pdf, hashed per point: the directions' lock. */
static uint64_t direction_hash(uint32_t kind, int with_pdf) {
  Fnv f = {0xcbf29ce484222325ull};
  int i;
  ok(strata_mapping_sample(kind, 0.0f, u2, 2 * N, pts, 3 * N), "sample");
  ok(strata_mapping_invert(kind, 0.0f, pts, 3 * N, back, 2 * N), "invert");
  ok(strata_mapping_pdf(kind, 0.0f, pts, 3 * N, pdf, N), "pdf");
  for (i = 0; i < N; i++) {
    fnv_floats(&f, pts + 3 * i, 3);
    fnv_floats(&f, back + 2 * i, 2);
    if (with_pdf) fnv_floats(&f, pdf + i, 1);
  }
  return f.h;
}

static uint64_t disk_hash(uint32_t kind) {
  Fnv f = {0xcbf29ce484222325ull};
  int i;
  ok(strata_mapping_sample(kind, 0.0f, u2, 2 * N, pts, 2 * N), "sample");
  ok(strata_mapping_invert(kind, 0.0f, pts, 2 * N, back, 2 * N), "invert");
  for (i = 0; i < N; i++) {
    fnv_floats(&f, pts + 2 * i, 2);
    fnv_floats(&f, back + 2 * i, 2);
  }
  return f.h;
}

static uint64_t cone_hash(void) {
  Fnv f = {0xcbf29ce484222325ull};
  int i;
  ok(strata_mapping_sample(STRATA_MAPPING_UNIFORM_CONE, 0.3f, u2, 2 * N, pts, 3 * N), "cone");
  ok(strata_mapping_invert(STRATA_MAPPING_UNIFORM_CONE, 0.3f, pts, 3 * N, back, 2 * N), "cone inverse");
  ok(strata_mapping_sample(STRATA_MAPPING_UNIFORM_CONE_SIN2, 1e-7f, u2, 2 * N, pts2, 3 * N), "tiny cone");
  ok(strata_mapping_invert(STRATA_MAPPING_UNIFORM_CONE_SIN2, 1e-7f, pts2, 3 * N, back2, 2 * N), "tiny inverse");
  for (i = 0; i < N; i++) {
    fnv_floats(&f, pts + 3 * i, 3);
    fnv_floats(&f, back + 2 * i, 2);
    fnv_floats(&f, pts2 + 3 * i, 3);
    fnv_floats(&f, back2 + 2 * i, 2);
  }
  return f.h;
}

static uint64_t onb_hash(void) {
  Fnv f = {0xcbf29ce484222325ull};
  int i;
  float *dirs = back; /* reused: 3 N floats */
  for (i = 0; i < N; i++) {
    dirs[3 * i] = 0.3f;
    dirs[3 * i + 1] = -0.2f;
    dirs[3 * i + 2] = 0.9f;
  }
  ok(strata_mapping_sample(STRATA_MAPPING_UNIFORM_SPHERE, 0.0f, u2, 2 * N, pts, 3 * N), "normals");
  ok(strata_onb_to_world(STRATA_ONB_DUFF, pts, 3 * N, dirs, 3 * N, pts2, 3 * N), "onb");
  ok(strata_onb_to_world(STRATA_ONB_AXIS_SWITCH, pts, 3 * N, dirs, 3 * N, back2, 3 * N), "axis switch");
  for (i = 0; i < N; i++) {
    fnv_floats(&f, pts2 + 3 * i, 3);
    fnv_floats(&f, back2 + 3 * i, 3);
  }
  return f.h;
}

static uint64_t ball_hash(void) {
  Fnv f = {0xcbf29ce484222325ull};
  int i;
  for (i = 0; i < N; i++) {
    u3[3 * i] = u2[2 * i];
    u3[3 * i + 1] = u2[2 * i + 1];
    /* The third coordinate runs along the grid's diagonal. */
    u3[3 * i + 2] = (u2[2 * i] + u2[2 * i + 1]) * 0.5f;
  }
  ok(strata_mapping_sample(STRATA_MAPPING_UNIFORM_BALL, 0.0f, u3, 3 * N, pts, 3 * N), "ball");
  ok(strata_mapping_invert(STRATA_MAPPING_UNIFORM_BALL, 0.0f, pts, 3 * N, back, 3 * N), "ball inverse");
  ok(strata_mapping_pdf(STRATA_MAPPING_UNIFORM_BALL, 0.0f, pts, 3 * N, pdf, N), "ball pdf");
  for (i = 0; i < N; i++) {
    fnv_floats(&f, pts + 3 * i, 3);
    fnv_floats(&f, back + 3 * i, 3);
    fnv_floats(&f, pdf + i, 1);
  }
  return f.h;
}

static void mapping_locks(const char *json) {
  struct {
    const char *name;
    uint64_t got;
  } cases[8];
  int c;
  grid(u2);
  cases[0].name = "uniform_sphere";
  cases[0].got = direction_hash(STRATA_MAPPING_UNIFORM_SPHERE, 1);
  cases[1].name = "uniform_hemisphere";
  cases[1].got = direction_hash(STRATA_MAPPING_UNIFORM_HEMISPHERE, 1);
  cases[2].name = "cosine_hemisphere";
  cases[2].got = direction_hash(STRATA_MAPPING_COSINE_HEMISPHERE, 1);
  cases[3].name = "concentric_disk";
  cases[3].got = disk_hash(STRATA_MAPPING_CONCENTRIC_DISK);
  cases[4].name = "polar_disk";
  cases[4].got = disk_hash(STRATA_MAPPING_POLAR_DISK);
  cases[5].name = "uniform_cone";
  cases[5].got = cone_hash();
  cases[6].name = "onb";
  cases[6].got = onb_hash();
  cases[7].name = "uniform_ball";
  cases[7].got = ball_hash();
  for (c = 0; c < 8; c++) {
    uint64_t want = 0;
    CHECK(read_hex(json, cases[c].name, &want), "%s: not in the locks file", cases[c].name);
    CHECK(cases[c].got == want, "%s: %016llx, locked %016llx", cases[c].name,
          (unsigned long long)cases[c].got, (unsigned long long)want);
  }
}

/* ---------------------------------------------------------- bad input */

static void expect(StrataStatus got, StrataStatus want, const char *what) {
  const char *message = strata_last_error();
  CHECK(got == want, "%s: status %d, expected %d", what, (int)got, (int)want);
  CHECK(message && message[0] != '\0', "%s: no message", what);
}

static void bad_input(void) {
  StrataSampler *s = NULL;
  float out[8], u[4] = {0.5f, 0.5f, 0.25f, 0.75f};
  float nan_normal[3] = {0.0f, 0.0f, 0.0f}, dir[3] = {1.0f, 0.0f, 0.0f};
  uint32_t pixels[2] = {1, 2}, idx[1] = {0};
  nan_normal[2] = strtof("nan", NULL);

  expect(strata_sampler_new(99, 16, 1, 0, 0, &s), STRATA_STATUS_INVALID_ARGUMENT, "unknown sampler kind");
  expect(strata_sampler_new(STRATA_SAMPLER_KIND_SOBOL, 0, 1, 0, 0, &s), STRATA_STATUS_INVALID_ARGUMENT,
         "0 spp");
  expect(strata_sampler_new(STRATA_SAMPLER_KIND_ZSOBOL, 16, 1, 0, 10, &s), STRATA_STATUS_INVALID_ARGUMENT,
         "zsobol without pixels");
  expect(strata_sampler_new(STRATA_SAMPLER_KIND_SOBOL, 16, 1, 0, 0, NULL), STRATA_STATUS_NULL_POINTER,
         "null out");
  expect(strata_sampler_start(NULL, 0, 0, 0), STRATA_STATUS_NULL_POINTER, "null sampler");
  expect(strata_sampler_next_2d(NULL, out, 2), STRATA_STATUS_NULL_POINTER, "null sampler 2d");
  CHECK(s == NULL, "a failed create leaves NULL");
  expect(strata_sampler_spp(NULL, NULL), STRATA_STATUS_NULL_POINTER, "spp of null");
  CHECK(strata_sampler_new(STRATA_SAMPLER_KIND_SOBOL, 16, 1, 0, 0, &s) == STRATA_STATUS_OK, "sobol");
  expect(strata_sampler_pixel_2d(s, out, 1), STRATA_STATUS_SHORT_BUFFER, "position into 1 float");
  expect(strata_sampler_spp(s, NULL), STRATA_STATUS_NULL_POINTER, "spp into null");
  expect(strata_sampler_next_2d(s, out, 1), STRATA_STATUS_SHORT_BUFFER, "2d into 1 float");
  expect(strata_sampler_next_1d(s, NULL, 1), STRATA_STATUS_NULL_POINTER, "1d into null");
  expect(strata_sampler_fill(s, pixels, 2, idx, 1, 9, out, 8), STRATA_STATUS_SHORT_BUFFER, "fill: short out");
  expect(strata_sampler_fill(s, pixels, 1, idx, 1, 2, out, 8), STRATA_STATUS_SHORT_BUFFER,
         "fill: short pixels");
  expect(strata_sampler_fill(s, NULL, 2, idx, 1, 2, out, 8), STRATA_STATUS_NULL_POINTER, "fill: null pixels");
  CHECK(strata_sampler_fill(s, NULL, 0, NULL, 0, 4, NULL, 0) == STRATA_STATUS_OK, "fill of nothing");
  strata_sampler_free(s);
  strata_sampler_free(NULL);

  expect(strata_mapping_sample(42, 0.0f, u, 4, out, 8), STRATA_STATUS_INVALID_ARGUMENT, "unknown mapping");
  expect(strata_mapping_invert(8, 0.0f, u, 3, out, 8), STRATA_STATUS_INVALID_ARGUMENT, "unknown inverse");
  expect(strata_mapping_pdf(STRATA_MAPPING_UNIFORM_BALL, 0.0f, u, 3, out, 0), STRATA_STATUS_SHORT_BUFFER,
         "pdf into nothing");
  expect(strata_onb_to_local(STRATA_ONB_AXIS_SWITCH, u, 3, u, 3, NULL, 3), STRATA_STATUS_NULL_POINTER,
         "local into null");
  {
    /* Samples outside [0, 1] (NaN too), and points that are not finite. */
    float bad_u[2] = {0.5f, 1.5f}, nan_point[3] = {0.0f, 0.0f, 1.0f};
    nan_point[1] = strtof("nan", NULL);
    expect(strata_mapping_sample(STRATA_MAPPING_CONCENTRIC_DISK, 0.0f, bad_u, 2, out, 8),
           STRATA_STATUS_INVALID_ARGUMENT, "a sample past 1");
    bad_u[1] = nan_point[1];
    expect(strata_mapping_sample(STRATA_MAPPING_UNIFORM_SPHERE, 0.0f, bad_u, 2, out, 8),
           STRATA_STATUS_INVALID_ARGUMENT, "a NaN sample");
    expect(strata_mapping_pdf(STRATA_MAPPING_UNIFORM_SPHERE, 0.0f, nan_point, 3, out, 8),
           STRATA_STATUS_INVALID_ARGUMENT, "a NaN point");
  }
  expect(strata_mapping_sample(STRATA_MAPPING_UNIFORM_SPHERE, 0.0f, u, 3, out, 8), STRATA_STATUS_SHORT_BUFFER,
         "half a row");
  expect(strata_mapping_sample(STRATA_MAPPING_UNIFORM_SPHERE, 0.0f, u, 4, out, 5), STRATA_STATUS_SHORT_BUFFER,
         "short points");
  expect(strata_mapping_pdf(STRATA_MAPPING_UNIFORM_SPHERE, 0.0f, NULL, 3, out, 8), STRATA_STATUS_NULL_POINTER,
         "null points");
  expect(strata_onb_to_world(7, dir, 3, dir, 3, out, 3), STRATA_STATUS_INVALID_ARGUMENT, "unknown basis");
  expect(strata_onb_to_world(STRATA_ONB_DUFF, nan_normal, 3, dir, 3, out, 3), STRATA_STATUS_INVALID_ARGUMENT,
         "NaN normal");
  expect(strata_onb_to_world(STRATA_ONB_DUFF, dir, 3, dir, 0, out, 3), STRATA_STATUS_SHORT_BUFFER,
         "no directions");
}

/* ---------------------------------------------------------- the BVH */

/* PCG32 (pcg-c-basic's pcg32_srandom and pcg32_random): the tracing
 * lock's ray generator, as rand_pcg's Pcg32::new(state, stream). */
typedef struct {
  uint64_t state, inc;
} Pcg;

static uint32_t pcg_next(Pcg *p) {
  uint64_t old = p->state;
  uint32_t xs, rot;
  p->state = old * 6364136223846793005ull + p->inc;
  xs = (uint32_t)(((old >> 18u) ^ old) >> 27u);
  rot = (uint32_t)(old >> 59u);
  return (xs >> rot) | (xs << ((0u - rot) & 31u));
}

static Pcg pcg_new(uint64_t state, uint64_t stream) {
  Pcg p;
  p.inc = (stream << 1u) | 1u;
  p.state = state + p.inc;
  p.state = p.state * 6364136223846793005ull + p.inc;
  return p;
}

/* The 24 high bits, times 2^-24: the core's next_f32. */
static float pcg_f32(Pcg *p) { return (float)(pcg_next(p) >> 8) * (1.0f / 16777216.0f); }

/* Aligned storage for a tree of `bytes`. */
static void *tree_storage(size_t bytes) {
  size_t rounded = (bytes + 63) / 64 * 64;
  return aligned_alloc(64, rounded ? rounded : 64);
}

/* Spheres (x, y, z, r rows) from a reference CSV; their count in *n. */
static float *read_spheres(const char *path, size_t *n) {
  char *text = read_file(path), *line, *save = NULL;
  float *out;
  size_t cap = 1024, k = 0;
  if (!text) return NULL;
  out = malloc(cap * 4 * sizeof *out);
  for (line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
    float v[4];
    char *p = line, *end;
    int i;
    if (strchr(line, 'x')) continue; /* the header */
    for (i = 0; i < 4; i++) {
      v[i] = strtof(p, &end);
      if (end == p) break;
      p = end + (*end == ',');
    }
    if (i < 4) continue;
    if (k == cap) out = realloc(out, (cap *= 2) * 4 * sizeof *out);
    memcpy(out + 4 * k++, v, sizeof v);
  }
  free(text);
  *n = k;
  return out;
}

/* The tracing lock of one layout: 4096 rays from PCG32(3), origins in
 * [lo, hi], directions uniform on the sphere (normalised), traced
 * through a BVH built into aligned storage. */
static uint64_t tracing_hash(const float *spheres, size_t n, const float lo[3], const float hi[3],
                             uint64_t stream) {
  enum { RAYS = 4096 };
  static StrataRay rays[RAYS];
  static StrataHit hits[RAYS];
  static uint8_t any[RAYS];
  Pcg rng = pcg_new(3, stream);
  Fnv f = {0xcbf29ce484222325ull};
  StrataBvh *bvh = NULL;
  size_t bytes = 0, i;
  void *storage;
  for (i = 0; i < RAYS; i++) {
    float u[2], d[3], len2, inv;
    int k;
    for (k = 0; k < 3; k++) {
      float span = hi[k] - lo[k];
      rays[i].origin[k] = lo[k] + span * pcg_f32(&rng);
    }
    u[0] = pcg_f32(&rng);
    u[1] = pcg_f32(&rng);
    ok(strata_mapping_sample(STRATA_MAPPING_UNIFORM_SPHERE, 0.0f, u, 2, d, 3), "ray direction");
    /* glam's normalize: times 1 / sqrt(x x + y y + z z). */
    len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    inv = 1.0f / sqrtf(len2);
    for (k = 0; k < 3; k++) rays[i].dir[k] = d[k] * inv;
    rays[i].t_min = 0.0f;
    rays[i].t_max = INFINITY;
  }
  ok(strata_bvh_storage_size(n, &bytes), "storage size");
  storage = tree_storage(bytes);
  ok(strata_bvh_build(spheres, 4 * n, storage, bytes, &bvh), "build");
  ok(strata_bvh_closest_hit(bvh, rays, RAYS, hits, RAYS), "closest");
  ok(strata_bvh_any_hit(bvh, rays, RAYS, any, RAYS), "any");
  for (i = 0; i < RAYS; i++) {
    fnv_word(&f, hits[i].id);
    fnv_word(&f, hits[i].id == UINT32_MAX ? 0u : bits(hits[i].t));
    fnv_word(&f, any[i]);
    CHECK(any[i] == (hits[i].id != UINT32_MAX), "ray %zu: any hit disagrees with the closest", i);
  }
  strata_bvh_free(bvh);
  free(storage);
  return f.h;
}

static void tracing_locks(const char *json, const char *data_dir) {
  struct {
    const char *name, *file;
    float lo[3], hi[3];
  } cases[2] = {{"course", "course.csv", {-2.0f, -0.5f, -2.0f}, {2.0f, 1.0f, 1.0f}},
                {"cover", "cover.csv", {-11.0f, 0.0f, -11.0f}, {11.0f, 2.0f, 11.0f}}};
  uint64_t stream = 0;
  int c;
  CHECK(read_hex(json, "pcg_stream", &stream), "pcg_stream: not in the locks file");
  for (c = 0; c < 2; c++) {
    char path[4200];
    size_t n = 0;
    float *spheres;
    uint64_t want = 0, got;
    snprintf(path, sizeof path, "%s/%s", data_dir, cases[c].file);
    spheres = read_spheres(path, &n);
    CHECK(spheres && n > 0, "%s: no spheres read", path);
    if (!spheres) continue;
    got = tracing_hash(spheres, n, cases[c].lo, cases[c].hi, stream);
    CHECK(read_hex(json, cases[c].name, &want), "%s: not in the locks file", cases[c].name);
    CHECK(got == want, "tracing %s (%zu spheres): %016llx, locked %016llx", cases[c].name, n,
          (unsigned long long)got, (unsigned long long)want);
    free(spheres);
  }
}

/* The caller's primitives: boxes, hit by a slab test in C. */
static int box_hit(void *user, uint32_t index, const StrataRay *r, float *t) {
  const StrataAabb *b = (const StrataAabb *)user + index;
  float near = -INFINITY, far = INFINITY, hit;
  int k;
  for (k = 0; k < 3; k++) {
    float inv = 1.0f / r->dir[k];
    float a = (b->min[k] - r->origin[k]) * inv, z = (b->max[k] - r->origin[k]) * inv;
    if (a > z) {
      float s = a;
      a = z;
      z = s;
    }
    near = a > near ? a : near;
    far = z < far ? z : far;
  }
  if (!(near <= far)) return 0;
  hit = near > r->t_min ? near : far;
  if (!(hit > r->t_min && hit < r->t_max)) return 0;
  *t = hit;
  return 1;
}

/* The primitive BVH against a brute-force loop over the same routine:
 * 10^4 rays over 1,000 boxes, closest (index and t bits) and any. */
static void primitive_bvh(void) {
  enum { BOXES = 1000, RAYS = 10000 };
  static StrataAabb boxes[BOXES];
  static StrataRay rays[RAYS];
  static StrataHit hits[RAYS];
  static uint8_t any[RAYS];
  Pcg rng = pcg_new(11, 5);
  StrataPrimitiveBvh *bvh = NULL;
  size_t bytes = 0, i, j, hit_count = 0;
  void *storage;
  for (i = 0; i < BOXES; i++) {
    int k;
    for (k = 0; k < 3; k++) {
      float c = 20.0f * pcg_f32(&rng) - 10.0f, h = 0.5f * pcg_f32(&rng);
      boxes[i].min[k] = c - h;
      boxes[i].max[k] = c + h;
    }
  }
  for (i = 0; i < RAYS; i++) {
    float u[2], d[3];
    int k;
    for (k = 0; k < 3; k++) rays[i].origin[k] = 24.0f * pcg_f32(&rng) - 12.0f;
    u[0] = pcg_f32(&rng);
    u[1] = pcg_f32(&rng);
    ok(strata_mapping_sample(STRATA_MAPPING_UNIFORM_SPHERE, 0.0f, u, 2, d, 3), "direction");
    memcpy(rays[i].dir, d, sizeof d);
    rays[i].t_min = 0.0f;
    rays[i].t_max = INFINITY;
  }
  ok(strata_primitive_bvh_storage_size(BOXES, &bytes), "storage size");
  storage = tree_storage(bytes);
  ok(strata_primitive_bvh_build(boxes, BOXES, box_hit, boxes, storage, bytes, &bvh), "build");
  ok(strata_primitive_bvh_closest_hit(bvh, rays, RAYS, hits, RAYS), "closest");
  ok(strata_primitive_bvh_any_hit(bvh, rays, RAYS, any, RAYS), "any");
  for (i = 0; i < RAYS; i++) {
    StrataHit want = {INFINITY, UINT32_MAX};
    for (j = 0; j < BOXES; j++) {
      float t;
      if (box_hit(boxes, (uint32_t)j, &rays[i], &t) && t < want.t) {
        want.t = t;
        want.id = (uint32_t)j;
      }
    }
    hit_count += want.id != UINT32_MAX;
    CHECK(hits[i].id == want.id && bits(hits[i].t) == bits(want.t), "ray %zu: tree %u at %g, loop %u at %g", i,
          hits[i].id, hits[i].t, want.id, want.t);
    CHECK(any[i] == (want.id != UINT32_MAX), "ray %zu: any hit", i);
  }
  CHECK(hit_count > RAYS / 10 && hit_count < RAYS, "%zu of %d rays hit: the test reaches nothing", hit_count,
        RAYS);
  strata_primitive_bvh_free(bvh);
  free(storage);
}

static void bvh_bad_input(void) {
  float sphere[4] = {0.0f, 0.0f, -3.0f, 1.0f}, bad_sphere[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  StrataRay ray = {{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, INFINITY};
  StrataHit hit;
  StrataAabb box = {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};
  StrataBvh *bvh = NULL;
  StrataPrimitiveBvh *pbvh = NULL;
  size_t bytes = 0;
  unsigned char *storage;
  bad_sphere[3] = 3e30f; /* beyond the tree's coordinate range */
  ok(strata_bvh_storage_size(1, &bytes), "size");
  storage = tree_storage(bytes + 64);
  expect(strata_bvh_storage_size(1, NULL), STRATA_STATUS_NULL_POINTER, "size into null");
  expect(strata_bvh_storage_size((size_t)1 << 40, &bytes), STRATA_STATUS_INVALID_ARGUMENT, "too many spheres");
  expect(strata_bvh_build(sphere, 4, NULL, bytes, &bvh), STRATA_STATUS_NULL_POINTER, "null storage");
  expect(strata_bvh_build(sphere, 4, storage + 4, bytes, &bvh), STRATA_STATUS_NULL_POINTER, "misaligned storage");
  expect(strata_bvh_build(sphere, 4, storage, bytes - 1, &bvh), STRATA_STATUS_SHORT_BUFFER, "short storage");
  expect(strata_bvh_build(sphere, 3, storage, bytes, &bvh), STRATA_STATUS_SHORT_BUFFER, "three floats");
  expect(strata_bvh_build(bad_sphere, 4, storage, bytes, &bvh), STRATA_STATUS_INVALID_ARGUMENT, "sphere out of range");
  {
    float negative[4] = {0.0f, 0.0f, -3.0f, -1.0f};
    expect(strata_bvh_build(negative, 4, storage, bytes, &bvh), STRATA_STATUS_INVALID_ARGUMENT, "negative radius");
  }
  ok(strata_bvh_build(sphere, 4, storage, bytes, &bvh), "build");
  ok(strata_bvh_closest_hit(bvh, &ray, 1, &hit, 1), "closest");
  CHECK(hit.id == 0 && hit.t == 2.0f, "the sphere at t = 2: %u at %g", hit.id, hit.t);
  expect(strata_bvh_closest_hit(NULL, &ray, 1, &hit, 1), STRATA_STATUS_NULL_POINTER, "null tree");
  expect(strata_bvh_closest_hit(bvh, &ray, 1, NULL, 1), STRATA_STATUS_NULL_POINTER, "null hits");
  expect(strata_bvh_closest_hit(bvh, &ray, 1, &hit, 0), STRATA_STATUS_SHORT_BUFFER, "no room for hits");
  ray.dir[2] = -2.0f;
  expect(strata_bvh_closest_hit(bvh, &ray, 1, &hit, 1), STRATA_STATUS_INVALID_ARGUMENT, "direction not unit");
  ray.dir[2] = -1.0f;
  ray.origin[0] = strtof("nan", NULL);
  expect(strata_bvh_any_hit(bvh, &ray, 1, (uint8_t *)&hit, 1), STRATA_STATUS_INVALID_ARGUMENT, "NaN origin");
  ray.origin[0] = 0.0f;
  ray.t_max = strtof("nan", NULL);
  expect(strata_bvh_closest_hit(bvh, &ray, 1, &hit, 1), STRATA_STATUS_INVALID_ARGUMENT, "NaN t_max");
  strata_bvh_free(bvh);
  strata_bvh_free(NULL);

  ok(strata_primitive_bvh_storage_size(1, &bytes), "size");
  expect(strata_primitive_bvh_build(&box, 1, NULL, &box, storage, bytes, &pbvh), STRATA_STATUS_NULL_POINTER,
         "no routine");
  box.max[0] = strtof("nan", NULL);
  expect(strata_primitive_bvh_build(&box, 1, box_hit, &box, storage, bytes, &pbvh),
         STRATA_STATUS_INVALID_ARGUMENT, "NaN box");
  box.max[0] = 1.0f;
  expect(strata_primitive_bvh_build(NULL, 1, box_hit, &box, storage, bytes, &pbvh), STRATA_STATUS_NULL_POINTER,
         "null boxes");
  ok(strata_primitive_bvh_build(&box, 1, box_hit, &box, storage, bytes, &pbvh), "build");
  ray.t_max = INFINITY;
  expect(strata_primitive_bvh_closest_hit(pbvh, &ray, 1, &hit, 0), STRATA_STATUS_SHORT_BUFFER, "no room");
  expect(strata_primitive_bvh_any_hit(pbvh, &ray, 1, NULL, 1), STRATA_STATUS_NULL_POINTER, "any into null");
  expect(strata_primitive_bvh_any_hit(NULL, &ray, 1, (uint8_t *)&hit, 1), STRATA_STATUS_NULL_POINTER,
         "null tree");
  expect(strata_primitive_bvh_storage_size(1, NULL), STRATA_STATUS_NULL_POINTER, "size into null");
  strata_primitive_bvh_free(pbvh);
  strata_primitive_bvh_free(NULL);
  free(storage);
}

/* ---------------------------------------------------------- the renderer */

/* The quoted strings of the array at `key`, up to `max`; their count. */
static int read_strings(const char *json, const char *key, char out[][64], int max) {
  const char *p = after_key(json, key);
  int n = 0;
  if (!p || !(p = strchr(p, '['))) return 0;
  while (n < max) {
    const char *a = strchr(p, '"'), *close = strchr(p, ']'), *b;
    if (!a || (close && close < a)) break;
    b = strchr(a + 1, '"');
    if (!b || b - a - 1 >= 64) break;
    memcpy(out[n], a + 1, (size_t)(b - a - 1));
    out[n][b - a - 1] = '\0';
    n++;
    p = b + 1;
  }
  return n;
}

/* Tiles first, first + 2, ... of a render, on one thread of this program. */
typedef struct {
  StrataRender *render;
  StrataRenderInfo info;
  StrataPixelSum *placed;
  uint32_t first;
  int failed;
} TileJob;

static void *render_tiles(void *arg) {
  TileJob *job = arg;
  size_t cap = (size_t)job->info.film_width * job->info.film_height;
  StrataPixelSum *film = malloc(cap * sizeof *film);
  uint32_t t;
  for (t = job->first; film && t < job->info.tiles; t += 2) {
    uint32_t rect[4], size[2], row;
    if (strata_render_tile(job->render, t, film, cap, rect, 4, size, 2) != STRATA_STATUS_OK ||
        size[0] != rect[2] || size[1] != rect[3]) {
      job->failed = 1;
      break;
    }
    for (row = 0; row < rect[3]; row++)
      memcpy(job->placed + (size_t)(rect[1] - job->info.y0 + row) * job->info.film_width + (rect[0] - job->info.x0),
             film + (size_t)row * size[0], size[0] * sizeof *film);
  }
  if (!film) job->failed = 1;
  free(film);
  return NULL;
}

/* A golden render through the C API: the whole frame on 2 threads, and
 * again tile by tile on two threads of this program; both hash to the
 * golden row. */
static void golden_row(const char *golden, const char *scene, const char *sampler) {
  char flags[16][64], key[128];
  const char *argv[24];
  int n = read_strings(golden, "flags", flags, 16), k;
  StrataRender *render = NULL;
  StrataRenderInfo info;
  StrataPixelSum *film, *placed, *tile_film;
  uint64_t want = 0, whole = 0, tiled = 0;
  uint32_t t;
  CHECK(n == 10, "golden flags: %d read", n);
  for (k = 0; k < n; k++) argv[k] = flags[k];
  argv[n++] = "--scene";
  argv[n++] = scene;
  argv[n++] = "--sampler";
  argv[n++] = sampler;
  argv[n++] = "--tile"; /* several tiles (the size never changes a pixel) */
  argv[n++] = "8";
  snprintf(key, sizeof key, "%s/%s", scene, sampler);
  CHECK(read_hex(golden, key, &want), "%s: not in the golden file", key);
  ok(strata_render_new(argv, (size_t)n, &render), key);
  if (!render) return;
  ok(strata_render_info(render, &info), "info");
  CHECK(info.width == 32 && info.height == 18 && info.spp == 4 && info.film_width == 32 && info.tiles > 1,
        "%s: %ux%u, %u spp, film %u wide, %u tiles", key, info.width, info.height, info.spp, info.film_width,
        info.tiles);
  film = calloc((size_t)info.film_width * info.film_height, sizeof *film);
  placed = calloc((size_t)info.film_width * info.film_height, sizeof *placed);
  tile_film = calloc((size_t)info.film_width * info.film_height, sizeof *tile_film);
  ok(strata_render_film(render, 2, film, (size_t)info.film_width * info.film_height), "film");
  ok(strata_film_hash(film, (size_t)info.film_width * info.film_height, &whole), "hash");
  CHECK(whole == want, "%s on 2 threads: %016llx, golden %016llx", key, (unsigned long long)whole,
        (unsigned long long)want);
  /* Tile by tile on two threads of this program, each placing its
   * tiles (even, odd) into the window's film. */
  {
    TileJob jobs[2];
    pthread_t threads[2];
    int j;
    for (j = 0; j < 2; j++) {
      jobs[j].render = render;
      jobs[j].info = info;
      jobs[j].placed = placed;
      jobs[j].first = (uint32_t)j;
      jobs[j].failed = 0;
      CHECK(pthread_create(&threads[j], NULL, render_tiles, &jobs[j]) == 0, "thread");
    }
    for (j = 0; j < 2; j++) {
      pthread_join(threads[j], NULL);
      CHECK(!jobs[j].failed, "%s: a tile thread failed", key);
    }
  }
  (void)tile_film;
  (void)t;
  ok(strata_film_hash(placed, (size_t)info.film_width * info.film_height, &tiled), "hash");
  CHECK(tiled == want, "%s tile by tile: %016llx, golden %016llx", key, (unsigned long long)tiled,
        (unsigned long long)want);
  {
    float rgb[3];
    ok(strata_film_rgb(film, 1, rgb, 3), "rgb");
    CHECK(rgb[0] >= 0.0f && rgb[0] < 100.0f && rgb[1] >= 0.0f && rgb[2] >= 0.0f, "%s: pixel 0 %g %g %g", key,
          rgb[0], rgb[1], rgb[2]);
  }
  free(film);
  free(placed);
  free(tile_film);
  strata_render_free(render);
}

static void renderer(const char *golden) {
  const char *bad_spp[] = {"--scene", "week09", "--spp", "0"};
  const char *unknown[] = {"--scene", "no-such-scene"};
  const char *output[] = {"--scene", "week09", "-o", "x.png"};
  const char *glued[] = {"--scene", "week09", "-ox.png"};
  const char *threads[] = {"--scene", "week09", "--threads", "2"};
  const char *typo[] = {"--scene", "week09", "--spp", "many"};
  const char *small[] = {"--scene", "week09", "--width", "8", "--height", "4", "--spp", "1"};
  const char *null_flag[] = {"--scene", NULL};
  StrataRender *render = NULL;
  StrataPixelSum film[32];
  uint32_t rect[4], size[2];
  golden_row(golden, "week09", "sobol");
  golden_row(golden, "cover", "independent");
  golden_row(golden, "showcase", "zsobol");

  expect(strata_render_new(bad_spp, 4, &render), STRATA_STATUS_INVALID_ARGUMENT, "--spp 0");
  CHECK(strstr(strata_last_error(), "--spp 0") != NULL, "the check's message: %s", strata_last_error());
  expect(strata_render_new(unknown, 2, &render), STRATA_STATUS_INVALID_ARGUMENT, "unknown scene");
  expect(strata_render_new(output, 4, &render), STRATA_STATUS_INVALID_ARGUMENT, "-o");
  CHECK(render == NULL, "a failed create leaves NULL");
  expect(strata_render_new(glued, 3, &render), STRATA_STATUS_INVALID_ARGUMENT, "-ox.png");
  expect(strata_render_new(threads, 4, &render), STRATA_STATUS_INVALID_ARGUMENT, "--threads");
  expect(strata_render_new(typo, 4, &render), STRATA_STATUS_INVALID_ARGUMENT, "--spp many");
  expect(strata_render_new(null_flag, 2, &render), STRATA_STATUS_NULL_POINTER, "null flag");
  expect(strata_render_new(NULL, 2, &render), STRATA_STATUS_NULL_POINTER, "null flags");
  ok(strata_render_new(small, 8, &render), "small render");
  expect(strata_render_film(render, 0, film, 32), STRATA_STATUS_INVALID_ARGUMENT, "0 threads");
  expect(strata_render_film(render, 100000, film, 32), STRATA_STATUS_INVALID_ARGUMENT, "100000 threads");
  expect(strata_render_film(render, 1, film, 31), STRATA_STATUS_SHORT_BUFFER, "short film");
  expect(strata_render_tile(render, 99, film, 32, rect, 4, size, 2), STRATA_STATUS_INVALID_ARGUMENT,
         "no such tile");
  expect(strata_render_tile(render, 0, film, 32, rect, 3, size, 2), STRATA_STATUS_SHORT_BUFFER, "short rect");
  expect(strata_render_info(NULL, NULL), STRATA_STATUS_NULL_POINTER, "null render");
  expect(strata_film_hash(NULL, 4, NULL), STRATA_STATUS_NULL_POINTER, "hash of null");
  {
    float rgb[2];
    expect(strata_film_rgb(film, 1, rgb, 2), STRATA_STATUS_SHORT_BUFFER, "rgb into 2 floats");
  }
  strata_render_free(render);
  strata_render_free(NULL);
}

/* ---------------------------------------------------------- the tabulated mapping */

/* The core's piecewise lock: table (row * 32 + column) mod 7; per grid
 * point the sample and its pdf, the pdf at the point, the inverse. */
static void piecewise(const char *json) {
  enum { S = STRATA_PIECEWISE_2D_SIZE };
  static float values[S * S], pts[2 * N], pdfs[N], again[N], back[2 * N];
  StrataPiecewise2d *table = NULL;
  Fnv f = {0xcbf29ce484222325ull};
  uint64_t want = 0;
  int i;
  for (i = 0; i < S * S; i++) values[i] = (float)(i % 7);
  grid(u2);
  ok(strata_piecewise2d_new(values, S * S, &table), "table");
  ok(strata_piecewise2d_sample(table, u2, 2 * N, pts, 2 * N, pdfs, N), "sample");
  ok(strata_piecewise2d_pdf(table, pts, 2 * N, again, N), "pdf");
  ok(strata_piecewise2d_invert(table, pts, 2 * N, back, 2 * N), "invert");
  for (i = 0; i < N; i++) {
    fnv_floats(&f, pts + 2 * i, 2);
    fnv_floats(&f, pdfs + i, 1);
    fnv_floats(&f, again + i, 1);
    fnv_floats(&f, back + 2 * i, 2);
  }
  CHECK(read_hex(json, "piecewise_fnv", &want), "piecewise_fnv: not in the locks file");
  CHECK(f.h == want, "piecewise: %016llx, locked %016llx", (unsigned long long)f.h, (unsigned long long)want);
  expect(strata_piecewise2d_sample(table, u2, 3, pts, 2 * N, pdfs, N), STRATA_STATUS_SHORT_BUFFER, "half a row");
  expect(strata_piecewise2d_pdf(NULL, pts, 2, again, 1), STRATA_STATUS_NULL_POINTER, "null table");
  strata_piecewise2d_free(table);
  strata_piecewise2d_free(NULL);
  table = NULL;
  expect(strata_piecewise2d_new(values, S * S - 1, &table), STRATA_STATUS_SHORT_BUFFER, "1023 values");
  values[5] = -1.0f;
  expect(strata_piecewise2d_new(values, S * S, &table), STRATA_STATUS_INVALID_ARGUMENT, "a negative value");
  for (i = 0; i < S * S; i++) values[i] = 0.0f;
  expect(strata_piecewise2d_new(values, S * S, &table), STRATA_STATUS_INVALID_ARGUMENT, "all zero");
  CHECK(table == NULL, "a failed create leaves NULL");
}

int main(int argc, char **argv) {
  char *json, *golden;
  const char *level = strata_simd_level();
  if (argc != 4) {
    fprintf(stderr, "usage: %s LOCKS_JSON GOLDEN_JSON EXPECTED_SIMD_LEVEL\n", argv[0]);
    return 2;
  }
  json = read_file(argv[1]);
  golden = read_file(argv[2]);
  if (!json || !golden) {
    fprintf(stderr, "cannot read %s or %s\n", argv[1], argv[2]);
    return 2;
  }
  printf("strata %s, output revision %u, simd %s\n", strata_version(), strata_output_revision(), level);
  CHECK(strcmp(level, argv[3]) == 0, "simd level %s, expected %s", level, argv[3]);
  CHECK(strata_output_revision() > 0, "output revision");
  sampler_locks(json);
  mapping_locks(json);
  {
    /* The reference layouts sit beside the locks file. */
    char dir[4096];
    const char *slash = strrchr(argv[1], '/');
    size_t len = slash ? (size_t)(slash - argv[1]) : 1;
    snprintf(dir, sizeof dir, "%.*s", (int)len, slash ? argv[1] : ".");
    tracing_locks(json, dir);
  }
  primitive_bvh();
  piecewise(json);
  bad_input();
  bvh_bad_input();
  renderer(golden);
  free(json);
  free(golden);
  if (failures) {
    fprintf(stderr, "%d failures\n", failures);
    return 1;
  }
  printf("all C checks passed\n");
  return 0;
}
