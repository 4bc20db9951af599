// Draws the pictures of docs/simulator.md: for a scene and motion, the rendered intensity at time T
// next to the events of [T - window, T] (ON red, OFF blue, on white), both enlarged 2x.
//
//   sim_event_frames SCENE MOTION T_SECONDS WINDOW_MS OUT.png [SEED]
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "asynevo/core/time.hpp"
#include "asynevo/sim/event_simulator.hpp"
#include "asynevo/sim/renderer.hpp"
#include "asynevo/sim/scene.hpp"
#include "asynevo/sim/simulate.hpp"

int main(int argc, char** argv) {
  using namespace asynevo;
  using namespace asynevo::sim;
  if (argc < 6) {
    std::fprintf(stderr, "usage: %s SCENE MOTION T_SECONDS WINDOW_MS OUT.png [SEED]\n", argv[0]);
    return 2;
  }
  try {
    SimulationSpec spec;
    spec.scene = argv[1];
    spec.motion = argv[2];
    const double t_s = std::atof(argv[3]);
    const double window_ms = std::atof(argv[4]);
    const std::string out = argv[5];
    spec.seed = argc > 6 ? std::strtoull(argv[6], nullptr, 10) : 1;
    spec.duration_s = isMotionPreset(spec.motion) ? t_s + 0.01 : 0;
    const CameraModel camera = CameraModel::davis240cEcd();
    const auto motion = makeMotion(spec);
    const Scene scene = isBuiltinScene(spec.scene) ? makeBuiltinScene(spec.scene, *motion, camera, spec.seed)
                                                   : loadSceneFile(spec.scene, *motion, camera, spec.seed);
    const int64_t t_end = motion->beginNs() + secondsToNs(t_s);
    const int64_t t_start = t_end - secondsToNs(window_ms * 1e-3);
    // Start a little before the window so every pixel has a settled reference.
    const int64_t sim_begin = std::max(motion->beginNs(), t_start - 200'000'000);
    cv::Mat events(camera.height(), camera.width(), CV_8UC3, cv::Scalar(255, 255, 255));
    cv::Mat counts(camera.height(), camera.width(), CV_32S, cv::Scalar(0));
    uint64_t n = 0;
    EventSimulator simulator(camera, scene, spec.sensor, spec.seed);
    simulator.run(*motion, sim_begin, t_end, [&](const std::vector<Event>& step) {
      for (const Event& e : step) {
        if (e.t_ns < t_start) continue;
        counts.at<int>(e.y, e.x) += e.polarity;
        ++n;
      }
    });
    for (int y = 0; y < camera.height(); ++y) {
      for (int x = 0; x < camera.width(); ++x) {
        const int c = counts.at<int>(y, x);
        if (c > 0) events.at<cv::Vec3b>(y, x) = cv::Vec3b(40, 40, 220);  // ON: red (BGR)
        if (c < 0) events.at<cv::Vec3b>(y, x) = cv::Vec3b(220, 90, 30);  // OFF: blue
      }
    }
    const Renderer renderer(camera, scene);
    const std::vector<float> intensity = renderer.render(motion->pose(t_end));
    cv::Mat grey(camera.height(), camera.width(), CV_8UC3);
    for (int y = 0; y < camera.height(); ++y) {
      for (int x = 0; x < camera.width(); ++x) {
        const auto v = static_cast<uint8_t>(
            std::clamp(intensity[static_cast<std::size_t>(y * camera.width() + x)] * 255.0f, 0.0f, 255.0f));
        grey.at<cv::Vec3b>(y, x) = cv::Vec3b(v, v, v);
      }
    }
    cv::Mat both;
    cv::hconcat(std::vector<cv::Mat>{grey, cv::Mat(camera.height(), 4, CV_8UC3, cv::Scalar(0, 0, 0)), events},
                both);
    cv::resize(both, both, cv::Size(), 2, 2, cv::INTER_NEAREST);
    if (!cv::imwrite(out, both)) throw std::runtime_error("cannot write " + out);
    std::printf("%s: %s / %s, t = %.3f s, %llu events in %.0f ms\n", out.c_str(), spec.scene.c_str(),
                spec.motion.c_str(), t_s, static_cast<unsigned long long>(n), window_ms);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
