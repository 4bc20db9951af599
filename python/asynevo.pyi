"""Type stub of the compiled module 'asynevo' (python/src; docs/guide/python.md)."""
import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

PathLike = Union[str, os.PathLike]
Sensor = Union[Tuple[int, int], str, None]
Config = Union[None, PathLike, Dict[str, Dict[str, Any]]]
Calibration = Union[PathLike, Dict[str, Any]]

class Error(RuntimeError):
    """Base class of AsynEVO's errors; the message names the file and line, record or byte."""

class InputError(Error):
    """Bad or unreadable input file: '<file>:<line>: <message>' (or record / byte offset)."""

class ConfigError(Error):
    """A configuration value that is missing, of the wrong type or out of range."""

def read_events(
    path: PathLike,
    format: str = "auto",
    sensor: Sensor = None,
    topic: str = "",
    max_events: Optional[int] = None,
    rectify_map: str = "",
) -> Dict[str, Any]:
    """Events of a file or dataset folder: {t: int64 ns, x, y: uint16, p: int8 (+1/-1), width, height,
    format, path, size_origin, rectify_map, stats}."""

def check_events(t: npt.ArrayLike, x: npt.ArrayLike, y: npt.ArrayLike, p: npt.ArrayLike, width: int,
                 height: int) -> None:
    """Raises ValueError (naming the array and index) for arrays run() and Stream.push() would reject."""

def run(
    source: Union[PathLike, Dict[str, Any]],
    calib: Optional[Calibration] = None,
    config: Config = None,
    *,
    format: str = "auto",
    sensor: Sensor = None,
    topic: str = "",
    backend: str = "window",
    out: Optional[PathLike] = None,
    rectify_map: str = "",
    camera_info_topic: str = "",
) -> Dict[str, Any]:
    """The offline pipeline on a dataset or event arrays: {trajectory (N x 8), knot_t_ns, velocities
    (N x 7), landmarks (M x 3), landmark_ids, landmark_observations, groundtruth, initialized, message,
    stats, summary, warnings, out}."""

def evaluate(
    gt: Union[PathLike, npt.ArrayLike],
    est: Union[PathLike, npt.ArrayLike],
    align: str = "sim3",
    velocities: Union[None, PathLike, npt.ArrayLike] = None,
    *,
    align_frames: int = -1,
    rel_lengths: Sequence[float] = (),
    max_time_diff_s: float = 0.02,
) -> Dict[str, Any]:
    """eval.json as a dict plus ate_rmse_m, ate_perc_of_path, gt_positions, aligned_est_positions."""

class Stream:
    """Push event batches, poll poses (live use); the same poses as run() on the same events."""

    def __init__(self, calib: Calibration, config: Config = None, *, sensor: Sensor = None,
                 backend: str = "window") -> None: ...
    def push(self, t: npt.ArrayLike, x: npt.ArrayLike, y: npt.ArrayLike, p: npt.ArrayLike) -> None: ...
    def push_events(self, events: Dict[str, Any]) -> None: ...
    def poll(self) -> Dict[str, np.ndarray]: ...
    def latest(self) -> Optional[np.ndarray]: ...
    def finish(self) -> None: ...
    def landmarks(self) -> Dict[str, np.ndarray]: ...
    @property
    def stats(self) -> Dict[str, Any]: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
