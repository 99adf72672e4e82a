"""What `auto` means for shadows (docs/shadows.md#auto): the cheapest setting within the
budget — no acne or leak (no wrong pixel beyond 2 px of the exact boundary), the boundary
within 1 px (p99), the colour within 1/255 away from the boundary — on every case the
study measured. The renderer resolves "auto" with the constant the study's run wrote into
scene/shadows.py (`AUTO_SHADOW_SETTING`); this is the rule that chooses it, and the check
that the constant is still the rule's answer (tests/test_shadow_study.py)."""

from __future__ import annotations

import statistics
from dataclasses import dataclass
from typing import Iterable

from ...scene import SHADOW_FILTERS
from .shadow_sweep import ShadowPoint, ShadowSetting

# Frame times within 5 % of the fastest are a tie, won by the larger map (the finer of
# equally cheap answers), then the cheaper filter, then the smaller bias. The larger map:
# on the study of 2026-11-25 a 256-texel map met the budget on every hard case at 256²
# images, 2 % cheaper than 512 texels, yet failed 12 of the random scenes 0-49 where 512
# texels fail 8 (docs/shadows.md#auto).
TIE = 0.05


@dataclass(frozen=True)
class ShadowBudget:
    wrong_far: int = 0  # pixels beyond 2 px of the exact boundary with the wrong state
    displacement_p99: float = 1.0  # px
    color_error: float = 1.0  # 1/255

    def allows(self, point: ShadowPoint) -> bool:
        return (point.wrong_far <= self.wrong_far and point.displacement_p99 <= self.displacement_p99
                and point.color_error <= self.color_error)


def qualifying_settings(points: Iterable[ShadowPoint], budget: ShadowBudget = ShadowBudget()) -> dict[ShadowSetting, float]:
    """Settings within the budget on every case they were measured on → their median frame
    cost (ms: CPU time where measured, ShadowPoint.cost_ms)."""
    by_setting: dict[ShadowSetting, list[ShadowPoint]] = {}
    for point in points:
        by_setting.setdefault(point.setting, []).append(point)
    return {setting: statistics.median(p.cost_ms for p in rows)
            for setting, rows in by_setting.items() if all(budget.allows(p) for p in rows)}


def cheapest_shadow_setting(points: Iterable[ShadowPoint], budget: ShadowBudget = ShadowBudget()) -> ShadowSetting | None:
    """The cheapest qualifying setting (None if none qualifies): least median frame cost;
    within 5 % of it (TIE), the larger map, then the filter earlier in SHADOW_FILTERS, then
    the smaller bias (the least a receiver is moved)."""
    qualifying = qualifying_settings(points, budget)
    if not qualifying:
        return None
    fastest = min(qualifying.values())
    ties = [s for s, ms in qualifying.items() if ms <= fastest * (1.0 + TIE)]
    return min(ties, key=lambda s: (-s.map_size, SHADOW_FILTERS.index(s.filter), s.bias))
