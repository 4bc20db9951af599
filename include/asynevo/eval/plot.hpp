#pragma once
// Figures for a run folder are drawn by tools/plot_run.py (matplotlib from Debian's
// python3-matplotlib). These helpers find the script and run it with the system interpreter.

#include <string>
#include <vector>

namespace asynevo::eval {

/// Locates plot_run.py: $ASYNEVO_TOOLS_DIR, then the source tree's tools/ (known at build time),
/// then <executable>/../share/asynevo/tools. Returns "" if none exists.
std::string findPlotScript();

/// The Python interpreter: $ASYNEVO_PYTHON if set, else /usr/bin/python3 (Debian's, which has
/// python3-matplotlib; a python3 earlier on PATH may lack it), else "python3" from PATH.
std::string pythonInterpreter();

/// Runs `python plot_run.py --run <run_dir> [extra...]`, inheriting stdout/stderr, and returns
/// its exit status. Throws Error when the script or the interpreter cannot be found or started.
int runPlotScript(const std::string& run_dir, const std::vector<std::string>& extra_args = {});

}  // namespace asynevo::eval
