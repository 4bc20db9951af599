#include "asynevo/sim/texture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "asynevo/core/error.hpp"
#include "asynevo/sim/renderer.hpp"
#include "asynevo/sim/scene.hpp"
#include "sim_test_util.hpp"

namespace asynevo::sim {
namespace {

TEST(Texture, MipLevelsAverageAndSamplingInterpolates) {
  // 4x4 checkerboard of single texels (0/1), texel 1 cm.
  std::vector<float> px(16);
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) px[static_cast<std::size_t>(4 * y + x)] = static_cast<float>((x + y) % 2);
  }
  const Texture t(px, 4, 4, 0.01, true, "test");
  EXPECT_EQ(t.levelCount(), 3);  // 4x4, 2x2, 1x1
  // At a texel centre with a tiny footprint: the texel itself.
  EXPECT_FLOAT_EQ(t.sample(0.005, 0.005, 1e-4), 0.0f);
  EXPECT_FLOAT_EQ(t.sample(0.015, 0.005, 1e-4), 1.0f);
  // Halfway between two texel centres: their mean.
  EXPECT_FLOAT_EQ(t.sample(0.01, 0.005, 1e-4), 0.5f);
  // Wraps around.
  EXPECT_FLOAT_EQ(t.sample(0.045, 0.005, 1e-4), 0.0f);
  EXPECT_FLOAT_EQ(t.sample(-0.005, 0.005, 1e-4), 1.0f);
  // A footprint of 2+ texels: the average level (0.5 everywhere).
  EXPECT_FLOAT_EQ(t.sample(0.013, 0.027, 0.02), 0.5f);
  EXPECT_FLOAT_EQ(t.sample(0.013, 0.027, 1.0), 0.5f);
}

TEST(Texture, ProceduralTexturesAreDeterministicAndInRange) {
  TextureOptions options;
  options.texels = 256;
  options.seed = 7;
  for (const auto& make : {makeShapesTexture, makeBlobsTexture}) {
    const auto a = make(options);
    const auto b = make(options);
    EXPECT_EQ(a->pixels(), b->pixels());
    options.seed = 8;
    EXPECT_NE(make(options)->pixels(), a->pixels());
    options.seed = 7;
    for (float v : a->pixels()) {
      ASSERT_GE(v, 0.0f);
      ASSERT_LE(v, 1.0f);
    }
  }
  const auto checker = makeCheckerboardTexture(options, 0.1);
  const double mean = std::accumulate(checker->pixels().begin(), checker->pixels().end(), 0.0) /
                      static_cast<double>(checker->pixels().size());
  EXPECT_NEAR(mean, 0.5, 1e-3);
  const auto stripes = makeStripesTexture(options, 0.25);
  EXPECT_NEAR(stripes->sample(0.06, 0.3, 1e-4), 0.9f, 1e-3);
  EXPECT_NEAR(stripes->sample(0.19, 0.3, 1e-4), 0.1f, 1e-3);
  EXPECT_THROW(makeShapesTexture(TextureOptions{1.0, 1000, 1}), std::invalid_argument);
}

// Anti-aliasing: a checkerboard far finer than a pixel must render as a nearly uniform grey, not as a
// moiré of black and white pixels (which would fire spurious events under motion).
TEST(Renderer, FineTextureIsPrefilteredNotAliased) {
  const CameraModel camera = CameraModel::pinhole(240, 180, 200, 200, 119.5, 89.5);
  const auto motion = makePresetMotion("static", 1.0);
  TextureOptions options;
  options.texels = 1024;
  Scene scene;
  // 2 mm squares seen from 3 m (one pixel covers 15 mm): ~7 squares per pixel.
  TexturedPlane plane = planeInFrontOfStart(*motion, camera, 3.0, makeCheckerboardTexture(options, 0.002));
  scene.planes.push_back(plane);
  const Renderer renderer(camera, scene);
  const std::vector<float> image = renderer.render(motion->pose(0));
  double sum = 0, sum_sq = 0;
  for (float v : image) {
    sum += v;
    sum_sq += static_cast<double>(v) * v;
  }
  const double mean = sum / static_cast<double>(image.size());
  const double stddev = std::sqrt(sum_sq / static_cast<double>(image.size()) - mean * mean);
  std::printf(
      "[ figure ] 2 mm checkerboard at 3 m: mean %.4f, std %.4f (point sampling would give std 0.4)\n", mean,
      stddev);
  EXPECT_NEAR(mean, 0.5, 0.01);
  EXPECT_LT(stddev, 0.02);
}

// The tile culling changes the work, not the image: rendering with every plane listed for every tile gives
// the same floats, bit for bit (boxes and room, DAVIS240C with its strong distortion and a wide pinhole).
TEST(Renderer, TileCullingGivesTheSameImageBitForBit) {
  const CameraModel cameras[] = {CameraModel::davis240cEcd(), CameraModel::pinhole(640, 480, 300, 300, 320, 240)};
  const auto motion = makePresetMotion("6dof", 5.0);
  for (const CameraModel& camera : cameras) {
    for (const char* name : {"boxes", "room"}) {
      const Scene scene = makeBuiltinScene(name, *motion, camera, 2);
      const Renderer renderer(camera, scene);
      double kept = 0, tiles = 0;
      for (int64_t t = 0; t <= 5'000'000'000; t += 1'250'000'000) {
        const Renderer::Frame culled = renderer.prepare(motion->pose(t));
        Renderer::Frame all = culled;
        all.tile_planes.clear();
        for (std::size_t k = 0; k + 1 < culled.tile_begin.size(); ++k) {
          all.tile_begin[k] = static_cast<uint32_t>(all.tile_planes.size());
          for (std::size_t i = 0; i < scene.planes.size(); ++i) all.tile_planes.push_back(static_cast<uint16_t>(i));
        }
        all.tile_begin.back() = static_cast<uint32_t>(all.tile_planes.size());
        std::vector<float> a(static_cast<std::size_t>(camera.width() * camera.height()));
        std::vector<float> b(a.size());
        renderer.render(culled, a.data(), 0, camera.height());
        renderer.render(all, b.data(), 0, camera.height());
        ASSERT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float))) << name << " t " << t;
        kept += static_cast<double>(culled.tile_planes.size());
        tiles += static_cast<double>(culled.tile_begin.size() - 1);
      }
      std::printf("[ figure ] %s, %dx%d: %.1f of %zu planes kept per tile on average\n", name, camera.width(),
                  camera.height(), kept / tiles, scene.planes.size());
    }
  }
}

TEST(Texture, LoadsImageFiles) {
  testing::TempDir dir;
  cv::Mat image(20, 40, CV_8U, cv::Scalar(0));
  image(cv::Rect(20, 0, 20, 20)).setTo(255);
  ASSERT_TRUE(cv::imwrite(dir.file("half.png"), image));
  const auto t = loadImageTexture(dir.file("half.png"), 0.4);  // 1 cm texels
  EXPECT_EQ(t->width(), 40);
  EXPECT_EQ(t->height(), 20);
  EXPECT_DOUBLE_EQ(t->texelSize(), 0.01);
  EXPECT_FALSE(t->repeats());
  EXPECT_FLOAT_EQ(t->sample(0.05, 0.1, 1e-4), 0.0f);
  EXPECT_FLOAT_EQ(t->sample(0.35, 0.1, 1e-4), 1.0f);
  EXPECT_FLOAT_EQ(t->sample(5.0, 0.1, 1e-4), 1.0f);  // clamped beyond the border
  try {
    loadImageTexture(dir.file("missing.png"), 1.0);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              dir.file("missing.png") + ": cannot read image (not found or not a format OpenCV reads)");
  }
}

TEST(Texture, PhotoTexturesAreMirrorTiledWithoutSeams) {
  testing::TempDir dir;
  cv::Mat image(16, 32, CV_8U);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) image.at<uint8_t>(y, x) = static_cast<uint8_t>(8 * x);
  ASSERT_TRUE(cv::imwrite(dir.file("ramp.png"), image));
  const auto t = loadPhotoTexture(dir.file("ramp.png"), 0.32);  // 1 cm texels
  EXPECT_EQ(t->width(), 64);
  EXPECT_EQ(t->height(), 32);
  EXPECT_TRUE(t->repeats());
  EXPECT_NEAR(t->sample(0.005, 0.05, 1e-4), 0.05f, 1e-6);                     // [0, 255] -> [0.05, 0.95]
  EXPECT_NEAR(t->sample(0.315, 0.05, 1e-4), 0.05f + 0.9f * 248 / 255, 1e-6);  // right border of the image
  EXPECT_NEAR(t->sample(0.325, 0.05, 1e-4), 0.05f + 0.9f * 248 / 255, 1e-6);  // its mirror: no seam
  EXPECT_NEAR(t->sample(0.635, 0.05, 1e-4), 0.05f, 1e-6);                     // mirror's end meets the start
  EXPECT_NEAR(t->sample(0.645, 0.05, 1e-4), 0.05f, 1e-6);
  EXPECT_THROW(loadPhotoTexture(dir.file("missing.png"), 1.0), InputError);
}

// The sparse texture: the requested number of separate dark polygons on white, nothing else.
TEST(Texture, SparseShapesAreFewAndSeparate) {
  TextureOptions options;
  options.tile_m = 2.0;
  options.seed = 3;
  const auto t = makeSparseShapesTexture(options, 1.5, 0.5);
  const int n = t->width();
  const std::vector<float>& px = t->pixels();
  // Dark components (8-connected, across the wrap).
  std::vector<int> label(px.size(), -1);
  int components = 0;
  std::size_t dark = 0;
  std::vector<int> stack;
  for (int start = 0; start < n * n; ++start) {
    if (px[static_cast<std::size_t>(start)] > 0.6f || label[static_cast<std::size_t>(start)] >= 0) continue;
    label[static_cast<std::size_t>(start)] = components;
    stack.push_back(start);
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      ++dark;
      const int x = i % n, y = i / n;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int j = ((y + dy + n) % n) * n + (x + dx + n) % n;
          if (px[static_cast<std::size_t>(j)] <= 0.6f && label[static_cast<std::size_t>(j)] < 0) {
            label[static_cast<std::size_t>(j)] = components;
            stack.push_back(j);
          }
        }
      }
    }
    ++components;
  }
  const double dark_share = static_cast<double>(dark) / static_cast<double>(px.size());
  std::printf("[ figure ] sparse texture, 2 m tile: %d polygons, %.2f %% dark; %s\n", components, 100 * dark_share,
              t->description().c_str());
  EXPECT_EQ(components, 6);  // 1.5 per m² on a 2 x 2 m tile, all separate
  EXPECT_NE(t->description().find("6 polygons"), std::string::npos);
  EXPECT_GT(dark_share, 0.005);
  EXPECT_LT(dark_share, 0.06);
}

}  // namespace
}  // namespace asynevo::sim
