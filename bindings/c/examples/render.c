/* A small path tracer in C on Strata's C API: the course's four spheres
 * under a sky, diffuse, traced a bounce at a time over every path at
 * once (one call per bounce does real work): Sobol' samples for the
 * pixel and each bounce, cosine-hemisphere directions turned into world
 * space by the normal's basis, and the BVH for every hit.
 *
 * usage: render OUT.ppm   (prints the image's FNV-1a hash; the C++
 * example, render.cpp, prints the same one) */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "strata.h"

enum { W = 64, H = 36, SPP = 16, DEPTH = 4, DIMS = 2 + 2 * DEPTH, PATHS = W * H * SPP };

/* The course's scene: ground, centre, left and right spheres. */
static const float SPHERES[4 * 4] = {0.0f, -100.5f, -1.0f, 100.0f, 0.0f, 0.0f, -1.2f, 0.5f,
                                     -1.0f, 0.0f, -1.0f, 0.5f,    1.0f, 0.0f, -1.0f, 0.5f};

static void check(StrataStatus s, const char *what) {
  if (s != STRATA_STATUS_OK) {
    fprintf(stderr, "%s: %s\n", what, strata_last_error());
    exit(1);
  }
}

int main(int argc, char **argv) {
  StrataSampler *sampler = NULL;
  StrataBvh *bvh = NULL;
  size_t bytes = 0, i;
  void *storage;
  uint32_t *pixels = malloc(2 * PATHS * sizeof *pixels), *index = malloc(PATHS * sizeof *index);
  float *u = malloc((size_t)PATHS * DIMS * sizeof *u);
  float *throughput = malloc(3 * PATHS * sizeof *throughput), *radiance = calloc(3 * PATHS, sizeof *radiance);
  float *normals = malloc(3 * PATHS * sizeof *normals), *local = malloc(3 * PATHS * sizeof *local);
  float *world = malloc(3 * PATHS * sizeof *world), *u2 = malloc(2 * PATHS * sizeof *u2);
  StrataRay *rays = malloc(PATHS * sizeof *rays);
  StrataHit *hits = malloc(PATHS * sizeof *hits);
  uint32_t *live = malloc(PATHS * sizeof *live);
  size_t n_live = PATHS;
  float image[3 * W * H];
  uint64_t hash = 0xcbf29ce484222325ull;
  FILE *out;
  int bounce;
  if (argc != 2) {
    fprintf(stderr, "usage: %s OUT.ppm\n", argv[0]);
    return 2;
  }
  if (!pixels || !index || !u || !throughput || !radiance || !normals || !local || !world || !u2 || !rays ||
      !hits || !live)
    return 1;

  /* Every path's samples in one call: the pixel, then a 2-D per bounce. */
  for (i = 0; i < PATHS; i++) {
    size_t p = i / SPP;
    pixels[2 * i] = (uint32_t)(p % W);
    pixels[2 * i + 1] = (uint32_t)(p / W);
    index[i] = (uint32_t)(i % SPP);
  }
  check(strata_sampler_new(STRATA_SAMPLER_KIND_SOBOL, SPP, 7, W, H, &sampler), "sampler");
  check(strata_sampler_fill(sampler, pixels, 2 * PATHS, index, PATHS, DIMS, u, (size_t)PATHS * DIMS), "fill");
  strata_sampler_free(sampler);

  /* The tree, in storage this program owns. */
  check(strata_bvh_storage_size(4, &bytes), "storage size");
  storage = aligned_alloc(64, (bytes + 63) / 64 * 64);
  check(strata_bvh_build(SPHERES, 16, storage, bytes, &bvh), "build");

  /* Camera rays: a pinhole at the origin looking down -z, 90 degrees
   * vertically. */
  for (i = 0; i < PATHS; i++) {
    float x = ((float)pixels[2 * i] + u[i * DIMS]) / (float)H * 2.0f - (float)W / (float)H;
    float y = 1.0f - ((float)pixels[2 * i + 1] + u[i * DIMS + 1]) / (float)H * 2.0f;
    float inv = 1.0f / sqrtf(x * x + y * y + 1.0f);
    StrataRay r = {{0.0f, 0.0f, 0.0f}, {x * inv, y * inv, -inv}, 0.0f, INFINITY};
    rays[i] = r;
    live[i] = (uint32_t)i;
    throughput[3 * i] = throughput[3 * i + 1] = throughput[3 * i + 2] = 1.0f;
  }

  for (bounce = 0; bounce < DEPTH && n_live > 0; bounce++) {
    size_t next = 0;
    check(strata_bvh_closest_hit(bvh, rays, n_live, hits, n_live), "closest hit");
    /* Misses see the sky; hits keep going, with their normal. */
    for (i = 0; i < n_live; i++) {
      uint32_t p = live[i];
      StrataRay *r = &rays[i];
      if (hits[i].id == UINT32_MAX) {
        float t = 0.5f * (r->dir[1] + 1.0f);
        float sky[3] = {1.0f - 0.5f * t, 1.0f - 0.3f * t, 1.0f};
        int k;
        for (k = 0; k < 3; k++) radiance[3 * p + k] += throughput[3 * p + k] * sky[k];
      } else {
        const float *s = SPHERES + 4 * hits[i].id;
        float n[3], len, inv;
        int k;
        for (k = 0; k < 3; k++) n[k] = (r->origin[k] + hits[i].t * r->dir[k] - s[k]) / s[3];
        len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        inv = 1.0f / len;
        for (k = 0; k < 3; k++) {
          normals[3 * next + k] = n[k] * inv;
          rays[next].origin[k] = r->origin[k] + hits[i].t * r->dir[k];
          throughput[3 * p + k] *= 0.5f;
        }
        u2[2 * next] = u[(size_t)p * DIMS + 2 + 2 * bounce];
        u2[2 * next + 1] = u[(size_t)p * DIMS + 3 + 2 * bounce];
        live[next++] = p;
      }
    }
    n_live = next;
    /* New directions for every live path in two calls: cosine-weighted
     * about z, then into each normal's basis. */
    check(strata_mapping_sample(STRATA_MAPPING_COSINE_HEMISPHERE, 0.0f, u2, 2 * n_live, local, 3 * n_live),
          "directions");
    check(strata_onb_to_world(STRATA_ONB_DUFF, normals, 3 * n_live, local, 3 * n_live, world, 3 * n_live),
          "to world");
    for (i = 0; i < n_live; i++) {
      float d[3] = {world[3 * i], world[3 * i + 1], world[3 * i + 2]};
      float inv = 1.0f / sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      int k;
      for (k = 0; k < 3; k++) rays[i].dir[k] = d[k] * inv;
      rays[i].t_min = 1e-3f; /* leave the surface */
      rays[i].t_max = INFINITY;
    }
  }
  strata_bvh_free(bvh);
  free(storage);

  /* The box filter: the mean of each pixel's samples. */
  for (i = 0; i < (size_t)W * H; i++) {
    int k, s;
    for (k = 0; k < 3; k++) {
      float sum = 0.0f;
      for (s = 0; s < SPP; s++) sum += radiance[3 * (i * SPP + s) + k];
      image[3 * i + k] = sum / (float)SPP;
    }
  }
  for (i = 0; i < 3 * W * H; i++) {
    uint32_t w;
    int k;
    memcpy(&w, &image[i], 4);
    for (k = 0; k < 4; k++) hash = (hash ^ ((w >> (8 * k)) & 0xff)) * 0x100000001b3ull;
  }
  out = fopen(argv[1], "wb");
  if (!out) return 1;
  fprintf(out, "P6\n%d %d\n255\n", W, H);
  for (i = 0; i < 3 * W * H; i++) {
    float v = sqrtf(image[i]);
    fputc((int)(255.0f * (v < 1.0f ? v : 1.0f) + 0.5f), out);
  }
  fclose(out);
  printf("%016llx\n", (unsigned long long)hash);
  free(pixels);
  free(index);
  free(u);
  free(throughput);
  free(radiance);
  free(normals);
  free(local);
  free(world);
  free(u2);
  free(rays);
  free(hits);
  free(live);
  return 0;
}
