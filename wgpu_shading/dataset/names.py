"""The files of a dataset run, checked before anything renders: no two jobs may write the
same file, and no job may write a file the run itself writes (cameras.json, report.json,
the folder lock).

Each job writes FOLDER/NAME.png, NAME_depth.(npy|png), NAME_normals_SPACE.npy, NAME_ids.png
and its record NAME.json, so different names can still meet: rows `x` and `x_depth` both
write `x_depth.png` with `--depth png16` (one job's depth map replaced by the other's colour
image, and reruns skipping both), `x` and `x_ids` meet at `x_ids.png`, and a view called
`cameras` has its record `cameras.json` overwritten by the folder's camera file. Every
output of every job is compared with every other's here (a dictionary of file names, so
100,000 jobs take a fraction of a second).

File names are compared case-folded: `View.png` and `view.png` are one file on macOS and
Windows, where a dataset is often copied.
"""

from __future__ import annotations

from ..errors import UsageError
from .jobs import Job

CAMERAS_FILE = "cameras.json"  # in every mesh folder: the cameras of its views
REPORT_FILE = "report.json"  # in the output folder: what the run did
LOCK_FILE = ".wgpu-shading.lock"  # in the output folder: held by the run writing there
RESERVED_IN_FOLDER = {CAMERAS_FILE: "the folder's camera file", LOCK_FILE: "the run's lock file"}
RESERVED_FOLDERS = {REPORT_FILE: "the run's report", LOCK_FILE: "the run's lock file"}


def job_files(job: Job) -> list[tuple[str, str]]:
    """(file name in the job's folder, what it is) for every file `job` writes."""
    kinds = {".png": "colour image", "_depth.": "depth map", "_normals_": "normal map", "_ids.png": "id mask"}
    files = []
    for name in job.outputs.file_names(job.name):
        rest = name[len(job.name):]
        kind = next((text for key, text in kinds.items() if rest.startswith(key)), "output")
        files.append((name, kind))
    files.append((f"{job.name}.json", "record"))
    return files


def check_output_names(jobs: list[Job]) -> None:
    """Raise a one-line UsageError naming both jobs (or the reserved file) when two outputs
    would be the same file."""
    owners: dict[tuple[str, str], tuple[int, str, str, str]] = {}  # (folder, name) → (job index, id, file, kind)
    for index, job in enumerate(jobs):
        folder = job.folder.casefold()
        if folder in (name.casefold() for name in RESERVED_FOLDERS):
            raise UsageError(
                f"batch: job {job.id!r}: folder {job.folder!r} is {RESERVED_FOLDERS.get(job.folder, 'reserved')}'s name; choose another folder"
            )
        for file_name, kind in job_files(job):
            key = (folder, file_name.casefold())
            for reserved, what in RESERVED_IN_FOLDER.items():
                if key[1] == reserved.casefold():
                    raise UsageError(
                        f"batch: job {job.id!r}: its {kind} {job.folder}/{file_name} would be {what}; "
                        f"the name {job.name!r} is reserved, choose another"
                    )
            other = owners.get(key)
            if other is not None and other[0] != index:
                _, other_id, other_file, other_kind = other
                raise UsageError(
                    f"batch: jobs {other_id!r} and {job.id!r} would write the same file {job.folder}/{file_name} "
                    f"(the {other_kind} of one, the {kind} of the other"
                    + (", names that differ only in case are one file on macOS and Windows" if other_file != file_name else "")
                    + "); rename one of them"
                )
            owners[key] = (index, job.id, file_name, kind)
