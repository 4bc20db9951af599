// 'asynevo eval': contract fixed by DESIGN.md §1; the implementation has not landed yet.
#include <string>

#include "commands.hpp"

namespace asynevo::cli {

void addEvalCommand(CLI::App& app) {
  static std::string gt, est, align = "sim3", out;
  static int align_frames = -1;
  auto* cmd = app.add_subcommand("eval", "Evaluate an estimated trajectory against ground truth");
  cmd->add_option("--gt", gt, "ground-truth trajectory (TUM)")->required();
  cmd->add_option("--est", est, "estimated trajectory (TUM)")->required();
  cmd->add_option("--align", align, "alignment (sim3, se3, posyaw, none)");
  cmd->add_option("--align-frames", align_frames, "poses used for the alignment (-1 = all)");
  cmd->add_option("--out", out, "folder for eval.json")->required();
  cmd->callback([] { throw NotImplemented("eval"); });
}

}  // namespace asynevo::cli
