#include "render/benchmark_rays.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <random>
#include <thread>
#include <unordered_map>

#include "render/frame_renderer.h"
#include "render/frame_types.glsl"
#include "shared/sampling.glsl"

namespace bounce::render {
namespace {

// Off the surface along its normal: enough for the walk not to find the
// surface itself again, relative to the point's magnitude (float spacing
// grows with it) and the scene's size.
glm::vec3 offsetOrigin(glm::vec3 point, glm::vec3 normal, float sceneExtent) {
  return point + normal * (1e-4f * (1.0f + glm::length(point)) + 1e-5f * sceneExtent);
}

// A cosine-distributed direction about `normal`, from two uniform numbers.
glm::vec3 cosineDirection(glm::vec3 normal, glm::vec2 u) {
  glm::vec3 tangent, bitangent;
  shared::buildOrthonormalBasis(normal, tangent, bitangent);
  const glm::vec3 local = shared::sampleCosineHemisphere(u);
  return glm::normalize(tangent * local.x + bitangent * local.y + normal * local.z);
}

BvhRay unboundedRay(glm::vec3 origin, glm::vec3 direction) {
  return {glm::vec4(origin, 0.0f), glm::vec4(direction, 1e30f)};
}

// Pixel i of a width x height image taken in 8x8 tiles (tiles row by row,
// pixels row by row inside a tile); tiles at the right and bottom edges are
// cut to the image, so every pixel comes exactly once.
glm::uvec2 tiledPixel(std::uint32_t width, std::uint32_t height, std::uint64_t i) {
  constexpr std::uint32_t kTile = 8;
  const std::uint32_t fullRows = height / kTile * kTile;
  const std::uint64_t rowBand = std::uint64_t(width) * kTile;  // pixels in one band of tiles
  if (i < std::uint64_t(fullRows) * width) {
    const auto band = std::uint32_t(i / rowBand);
    const std::uint64_t inBand = i % rowBand;
    const auto tileX = std::uint32_t(inBand / (kTile * kTile));
    const std::uint32_t tileWidth = std::min(kTile, width - tileX * kTile);
    const auto inTile = std::uint32_t(inBand - std::uint64_t(tileX) * kTile * kTile);
    return {tileX * kTile + inTile % tileWidth, band * kTile + inTile / tileWidth};
  }
  // The last band, shorter than a tile.
  const std::uint32_t bandHeight = height - fullRows;
  const std::uint64_t inBand = i - std::uint64_t(fullRows) * width;
  const auto tileX = std::uint32_t(inBand / (kTile * bandHeight));
  const std::uint32_t tileWidth = std::min(kTile, width - tileX * kTile);
  const auto inTile = std::uint32_t(inBand - std::uint64_t(tileX) * kTile * bandHeight);
  return {tileX * kTile + inTile % tileWidth, fullRows + inTile / tileWidth};
}

}  // namespace

std::vector<BvhRay> boundsRays(const scene::Scene& scene, std::uint32_t count) {
  const scene::Bounds sceneBounds = scene::worldBounds(scene, 0.0f);
  // A scene with nothing in it has no bounds (they are inverted and infinite): its rays start around the origin.
  const scene::Bounds bounds = sceneBounds.empty() ? scene::Bounds{glm::vec3(-1.0f), glm::vec3(1.0f)} : sceneBounds;
  std::mt19937 random(1234);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> gauss;
  std::vector<BvhRay> rays(count);
  for (BvhRay& ray : rays) {
    const glm::vec3 origin = bounds.min + bounds.extent() * glm::vec3(unit(random), unit(random), unit(random));
    const glm::vec3 direction =
        glm::normalize(glm::vec3(gauss(random), gauss(random), gauss(random)) + glm::vec3(1e-6f));
    ray = unboundedRay(origin, direction);
  }
  return rays;
}

std::vector<BvhRay> surfaceRays(const scene::Scene& scene, std::uint32_t count) {
  struct Placed {
    glm::vec3 p0, e1, e2;
  };
  std::vector<Placed> triangles;
  std::vector<double> cumulativeArea;
  double area = 0.0;
  for (const scene::Instance& instance : scene::instancesAt(scene, 0.0f)) {
    const scene::Mesh& mesh = scene.meshes[std::size_t(instance.mesh)];
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const auto corner = [&](std::size_t c) {
        return glm::vec3(instance.objectToWorld * glm::vec4(mesh.positions[mesh.indices[t + c]], 1.0f));
      };
      const glm::vec3 p0 = corner(0), e1 = corner(1) - p0, e2 = corner(2) - p0;
      const double a = 0.5 * double(glm::length(glm::cross(e1, e2)));
      if (!(a > 0.0) || !std::isfinite(a)) continue;
      area += a;
      triangles.push_back({p0, e1, e2});
      cumulativeArea.push_back(area);
    }
  }
  if (triangles.empty()) return boundsRays(scene, count);
  const float extent = glm::length(scene::worldBounds(scene, 0.0f).extent());
  std::mt19937 random(1234);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<BvhRay> rays(count);
  for (BvhRay& ray : rays) {
    const double pick = double(unit(random)) * area;
    const std::size_t index =
        std::size_t(std::lower_bound(cumulativeArea.begin(), cumulativeArea.end(), pick) - cumulativeArea.begin());
    const Placed& triangle = triangles[std::min(index, triangles.size() - 1)];
    float u = unit(random), v = unit(random);
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    const glm::vec3 p = triangle.p0 + triangle.e1 * u + triangle.e2 * v;
    glm::vec3 normal = glm::normalize(glm::cross(triangle.e1, triangle.e2));
    if (unit(random) < 0.5f) normal = -normal;
    const glm::vec3 direction = cosineDirection(normal, glm::vec2(unit(random), unit(random)));
    ray = unboundedRay(offsetOrigin(p, normal, extent), direction);
  }
  return rays;
}

VisibleSurfaceRays visibleSurfaceRays(const SceneBvh& bvh, const scene::CameraPose& camera, std::uint32_t width,
                                      std::uint32_t height, std::uint32_t count,
                                      const std::function<void(std::uint64_t done, std::uint64_t total)>& progress) {
  VisibleSurfaceRays result;
  result.pixels = width * height;
  const shared::GpuCamera gpu = gpuCamera(camera, width, height);
  const glm::vec3 eye = camera.position;
  const glm::vec2 size{float(width), float(height)};
  std::unordered_map<std::uint32_t, std::size_t> recordOf;  // caller's instance index -> its TLAS record
  for (std::size_t r = 0; r < bvh.instances().size(); ++r) recordOf[bvh.instances()[r].info.z] = r;

  // Each pixel's surface (a point and the side of its geometric normal that
  // faces the camera), or none: threads take interleaved pixels.
  struct Surface {
    glm::vec3 point{0.0f};
    glm::vec3 normal{0.0f};
    bool seen = false;
  };
  std::vector<Surface> surfaces(result.pixels);
  const unsigned threadCount = std::clamp(std::thread::hardware_concurrency(), 1u, 64u);
  std::vector<std::thread> threads;
  std::vector<std::exception_ptr> failures(threadCount);
  std::atomic<std::uint64_t> traced{0};
  std::atomic<unsigned> running{threadCount};
  for (unsigned worker = 0; worker < threadCount; ++worker)
    threads.emplace_back([&, worker] {
      try {
        std::uint64_t sinceReported = 0;  // pixels this thread took since it last added them to `traced`
        for (std::uint64_t i = worker; i < result.pixels; i += threadCount) {
          if (++sinceReported == 4096) {
            traced.fetch_add(sinceReported, std::memory_order_relaxed);
            sinceReported = 0;
          }
          const glm::uvec2 pixel = tiledPixel(width, height, i);
          const glm::vec3 direction = shared::cameraRayDirection(gpu, glm::vec2(pixel) + 0.5f, size);
          const BvhHit hit = bvh.traceClosest(eye, direction, 0.0f, shared::kNoHit);
          if (hit.instance == shared::kBvhInvalidIndex) continue;
          const BvhInstance& record = bvh.instances()[recordOf.at(hit.instance)];
          const glm::uvec4 corners = bvh.triangles()[hit.triangle];
          const auto world = [&](std::uint32_t vertex) {
            return shared::bvhTransformPoint(record.objectToWorld, glm::vec3(bvh.positions()[vertex]));
          };
          const glm::vec3 p0 = world(corners.x), p1 = world(corners.y), p2 = world(corners.z);
          const glm::vec3 cross = glm::cross(p1 - p0, p2 - p0);
          const float length = glm::length(cross);
          if (!(length > 0.0f) || !std::isfinite(length)) continue;
          glm::vec3 normal = cross / length;
          if (glm::dot(normal, direction) > 0.0f) normal = -normal;
          const glm::vec2 b = hit.barycentrics;
          surfaces[i] = {p0 + (p1 - p0) * b.x + (p2 - p0) * b.y, normal, true};
        }
      } catch (...) {
        failures[worker] = std::current_exception();
      }
      running.fetch_sub(1);
    });
  while (progress && running.load() > 0) {
    progress(std::min<std::uint64_t>(traced.load(std::memory_order_relaxed), result.pixels), result.pixels);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  for (std::thread& thread : threads) thread.join();
  if (progress) progress(result.pixels, result.pixels);
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);

  std::vector<std::uint32_t> visible;
  for (std::uint32_t i = 0; i < result.pixels; ++i)
    if (surfaces[i].seen) visible.push_back(i);
  result.visiblePixels = std::uint32_t(visible.size());
  if (visible.empty()) return result;
  const float extent = glm::length(bvh.tlasBounds().max - bvh.tlasBounds().min);
  std::mt19937 random(1234);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  result.rays.resize(count);
  for (std::uint32_t r = 0; r < count; ++r) {
    const Surface& s = surfaces[visible[std::size_t(std::uint64_t(r) * visible.size() / count)]];
    const glm::vec3 direction = cosineDirection(s.normal, glm::vec2(unit(random), unit(random)));
    result.rays[r] = unboundedRay(offsetOrigin(s.point, s.normal, extent), direction);
  }
  return result;
}

}  // namespace bounce::render
