"""What a difference between two images looks like, in plain language: a shift by a pixel
or two, swapped or rotated color channels, a brighter or darker image or a change of hue,
a highlight that dimmed or appeared, and where the differing pixels lie. Every guess is
tested on the pixels, not assumed. `compare` puts these lines in a failure's message.

Pure numpy; works on the (H, W, 4) uint8 arrays `compare` has already checked.
"""

from __future__ import annotations

import itertools

import numpy as np

CHANNELS = ("red", "green", "blue", "alpha")
_SHIFT_RADIUS = 2  # offsets tried when looking for a shift, in pixels


def diagnose(a: np.ndarray, e: np.ndarray, delta: np.ndarray, over: np.ndarray, threshold: int) -> list[str]:
    """Plain-language guesses at what the difference is; each guess is tested, not assumed.

    a, e: actual and expected (H, W, 4) uint8; delta: |a − e| per channel; over: the
    pixels differing by more than `threshold`."""
    notes: list[str] = []
    if not over.any():
        return notes
    swapped = _channel_permutation(a, e, threshold, int(over.sum()))
    if swapped:
        notes.append(swapped)
    shift = _shift(a, e, threshold)
    if shift:
        notes.append(shift)
    notes.append(_channels(delta, over))
    notes.append(_brightness(a, e, over))
    highlight = _highlight(a, e, over)
    if highlight and not shift and not swapped:
        notes.append(highlight)
    notes.append(_region(over))
    return notes


def _channels(delta: np.ndarray, over: np.ndarray) -> str:
    totals = delta[over].astype(np.float64).sum(axis=0)  # per channel, over the differing pixels
    share = totals / max(totals.sum(), 1e-12)
    order = np.argsort(-share)
    first, second = int(order[0]), int(order[1])
    if share[first] >= 0.6:
        return f"the largest differences are in the {CHANNELS[first]} channel ({share[first]:.0%} of the total)"
    if share[first] + share[second] >= 0.85:
        return f"the differences are in the {CHANNELS[first]} and {CHANNELS[second]} channels ({share[first] + share[second]:.0%} of the total)"
    if share[3] < 0.1:
        return "the differences are spread over the red, green and blue channels alike"
    return "the differences are spread over all channels, alpha included"


def _brightness(a: np.ndarray, e: np.ndarray, over: np.ndarray) -> str:
    signed = a[over][:, :3].astype(np.float64) - e[over][:, :3].astype(np.float64)  # (n, 3)
    channel_mean = signed.mean(axis=0)
    per_pixel = signed.mean(axis=1)
    if not np.abs(signed).any():
        return "only alpha differs"
    changes = ", ".join(f"{CHANNELS[i]} {channel_mean[i]:+.0f}" for i in range(3))
    signs = {int(np.sign(round(v))) for v in channel_mean} - {0}
    if len(signs) > 1:
        return f"a change of hue, not of brightness: mean change over the differing pixels {changes} (/255)"
    mean = per_pixel.mean()
    if abs(mean) >= 0.6 * np.abs(per_pixel).mean():
        word = "brighter" if mean > 0 else "darker"
        return f"the actual image is {word} there: mean change over the differing pixels {changes} (/255)"
    brighter = float((per_pixel > 0).mean())
    return f"mixed: {brighter:.0%} of the differing pixels are brighter, {1 - brighter:.0%} darker"


def _highlight(a: np.ndarray, e: np.ndarray, over: np.ndarray) -> str | None:
    """Did the brightest spot of one image (a specular highlight, most often) dim or appear?"""
    count = max(4, int(0.002 * over.size))
    luminance_e = e[:, :, :3].astype(np.float64) @ (0.2126, 0.7152, 0.0722)
    luminance_a = a[:, :, :3].astype(np.float64) @ (0.2126, 0.7152, 0.0722)
    for image, other, word in ((luminance_e, luminance_a, "dimmed or gone"), (luminance_a, luminance_e, "new")):
        top = np.argsort(image, axis=None)[-count:]
        hit = over.reshape(-1)[top]
        drop = image.reshape(-1)[top] - other.reshape(-1)[top]
        # Only a large change of the brightest spot counts: at least 25/255 and 15 % of its level.
        if hit.mean() >= 0.5 and np.median(drop) >= max(25.0, 0.15 * np.median(image.reshape(-1)[top])):
            if word == "new":
                return f"a bright spot (highlight?) in the actual image is not in the expected one: its brightest pixels are {np.median(drop):.0f}/255 brighter"
            return f"the expected image's brightest spot (highlight?) is {word}: {np.median(drop):.0f}/255 darker in the actual image"
    return None


def _region(over: np.ndarray) -> str:
    rows = np.flatnonzero(over.any(axis=1))
    cols = np.flatnonzero(over.any(axis=0))
    r0, r1, c0, c1 = int(rows[0]), int(rows[-1]), int(cols[0]), int(cols[-1])
    height, width = over.shape
    box = (r1 - r0 + 1) * (c1 - c0 + 1)
    where = f"rows {r0}–{r1}, cols {c0}–{c1}"
    share = box / (height * width)
    if share <= 0.1:
        return f"a local difference: all differing pixels lie within {where} ({share:.1%} of the image)"
    return f"differing pixels spread over {where} ({share:.0%} of the image)"


def _shift(a: np.ndarray, e: np.ndarray, threshold: int) -> str | None:
    """Does moving the actual image by a few pixels make it match much better?"""
    r = _SHIFT_RADIUS
    height, width = e.shape[:2]
    if height <= 4 * r or width <= 4 * r:
        return None
    core = e[r : height - r, r : width - r].astype(np.int16)

    def count(dy: int, dx: int) -> int:
        # actual[y + dy, x + dx] against expected[y, x]: content moved by (dx, dy) in the actual image
        window = a[r + dy : height - r + dy, r + dx : width - r + dx].astype(np.int16)
        return int((np.abs(window - core).max(axis=2) > threshold).sum())

    base = count(0, 0)
    if base == 0:
        return None
    best = min(((count(dy, dx), dy, dx) for dy in range(-r, r + 1) for dx in range(-r, r + 1) if (dy, dx) != (0, 0)))
    best_count, dy, dx = best
    if best_count > 0.2 * base:
        return None
    moves = []
    if dx:
        moves.append(f"{abs(dx)} pixel{'s' if abs(dx) > 1 else ''} {'right' if dx > 0 else 'left'}")
    if dy:
        moves.append(f"{abs(dy)} pixel{'s' if abs(dy) > 1 else ''} {'down' if dy > 0 else 'up'}")
    return (
        f"a shift: the actual image is the expected one moved {' and '.join(moves)} "
        f"(that offset leaves {best_count} of {base} differing pixels)"
    )


def _channel_permutation(a: np.ndarray, e: np.ndarray, threshold: int, base: int) -> str | None:
    """Does reordering the actual image's color channels make it match much better?"""
    best = None
    for perm in itertools.permutations(range(3)):
        if perm == (0, 1, 2):
            continue
        permuted = a[:, :, list(perm) + [3]].astype(np.int16)
        count = int((np.abs(permuted - e.astype(np.int16)).max(axis=2) > threshold).sum())
        if best is None or count < best[0]:
            best = (count, perm)
    if best is None or best[0] > 0.2 * base:
        return None
    perm = best[1]
    moved = [i for i in range(3) if perm[i] != i]
    if len(moved) == 2:
        i, j = moved
        return f"swapped color channels: {CHANNELS[i]} and {CHANNELS[j]} are exchanged (swapping them back leaves {best[0]} differing pixels)"
    # perm[i] = j: expected channel i holds what the actual image has in channel j
    mapping = ", ".join(f"actual {CHANNELS[perm[i]]} → {CHANNELS[i]}" for i in range(3))
    return f"rotated color channels ({mapping} would match; leaves {best[0]} differing pixels)"
