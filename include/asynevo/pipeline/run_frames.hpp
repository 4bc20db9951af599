#pragma once
// 'asynevo run --frames DIR': the frame-based baseline (ours, not DSO; docs/results/repeated_texture.md).
// Intensity frames (frames/frame_folder.hpp) are tracked by KLT (frames/klt_tracker.hpp) and the tracks,
// sampled at the frame times, go to the same estimator as the event frontend's, in the event pipeline's
// call order: time markers every 1 ms up to a frame's time, then that frame's measurements. One thread,
// deterministic. Writes the same run folder as runDataset (docs/pipeline.md).

#include "asynevo/frames/klt_tracker.hpp"
#include "asynevo/pipeline/run.hpp"

namespace asynevo::pipeline {

struct FramesRunOptions {
  std::string frames;       ///< folder with images.txt (and calib.txt / camchain.yaml, groundtruth.txt)
  std::string calib;        ///< "" = the folder's calib.txt, else its camchain.yaml
  std::string config_path;  ///< "" = defaults
  BackendKind backend = BackendKind::kWindow;
  std::string out;
  frames::KltOptions klt;
};

/// Runs the frame folder end to end and writes the run folder. Throws InputError naming the file for
/// a missing images.txt or calibration, an unreadable or mis-sized image.
RunSummary runFrameFolder(const FramesRunOptions& options);

}  // namespace asynevo::pipeline
