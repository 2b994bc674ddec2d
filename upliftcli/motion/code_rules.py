"""What the codes ask of a suite of records (one horizontal component per record, a planar model).

* ASCE 7-22 chapter 16: at least 11 records (16.2.2); the period range from the structure's
  periods (16.2.3.1): upper bound at least twice the largest first-mode period, lower bound at
  most 20 % of the smallest first-mode period and low enough to take the modes that reach 90 %
  of the mass; amplitude-scaled suites: the mean spectrum not below 90 % of the target over the
  range (16.2.3.2); spectrally matched suites: not below 110 % (16.2.3.3); design values: the
  mean of the responses.
* EN 1998-1: at least 3 accelerograms; the mean spectrum not below 90 % of the elastic spectrum
  between 0.2 T_1 and 2 T_1 (3.2.3.1.2(4)); the mean response from at least 7 analyses, the most
  unfavourable (maximum) otherwise (4.3.3.4.3(3)); artificial records with a stationary part of
  at least 10 s (3.2.3.1.2(3)).
* "mean": no code; any number of records, the mean not below 100 % of the target, the period
  range of ASCE 7-22.
"""

from __future__ import annotations

from dataclasses import dataclass

#: how a suite is brought to its target (suites.build_suite)
SCALINGS = ("none", "amplitude", "match")
#: the deck fields of [ground_motion] that only a suite takes (deck/motion.py, deck/suite.py)
SUITE_ONLY = ("scaling", "suite_factor")


@dataclass(frozen=True)
class CodeRule:
    """The suite requirements of one code.

    name: "asce7-22", "ec8" or "mean"; label: the clauses, in words;
    min_records: the fewest records the code accepts; mean_from: the fewest records for which the
    design value is the mean (below: the maximum; 1 = always the mean);
    scaled_mean, matched_mean: the lowest allowed mean S_a/target over the period range for an
    amplitude-scaled and for a spectrally matched suite [-];
    range_rule: "asce7-22" (lower bound min(0.2 T_1, T_90)) or "ec8" (0.2 T_1 to 2 T_1);
    stationary_duration: the shortest stationary part of an artificial record [s].
    """

    name: str
    label: str
    min_records: int
    mean_from: int
    scaled_mean: float
    matched_mean: float
    range_rule: str
    stationary_duration: float = 0.0

    def statistic(self, count: int) -> str:
        """'mean' or 'max': the design value from `count` records."""
        return "mean" if count >= self.mean_from else "max"

    def mean_minimum(self, scaling: str) -> float:
        """The lowest allowed mean S_a/target for a suite scaled by `scaling` ('none',
        'amplitude' or 'match'; records used as they are count as amplitude-scaled)."""
        return self.matched_mean if scaling == "match" else self.scaled_mean

    def count_warnings(self, count: int) -> list[str]:
        """One message per requirement on the number of records that `count` does not meet."""
        messages = []
        if count < self.min_records:
            messages.append(f"{self.label} asks for at least {self.min_records} records; the suite has {count}")
        if count < self.mean_from:
            messages.append(f"{self.label}: with fewer than {self.mean_from} records the design value is the "
                            f"maximum of the responses, not the mean ({count} records)")
        return messages

    def period_range(self, first_period: float, shortest_first_period: float, period_90: float
                     ) -> tuple[tuple[float, float], str]:
        """((lower, upper) [s], how they were found) from the structure's periods [s]:
        first_period: the largest first-mode period (upper bound 2 x); shortest_first_period: the
        smallest first-mode period (lower bound 0.2 x); period_90: the period of the last mode
        needed for 90 % of the mass (ASCE 7-22 only)."""
        upper = 2.0 * first_period
        if self.range_rule == "ec8":
            lower = 0.2 * shortest_first_period
            note = (f"{self.label}: 0.2 T_1 = {lower:.4g} s to 2 T_1 = {upper:.4g} s "
                    f"(T_1 = {shortest_first_period:.4g} s and {first_period:.4g} s)")
            return (lower, upper), note
        lower = min(0.2 * shortest_first_period, period_90)
        note = (f"{self.label}: lower bound min(0.2 T_1 = {0.2 * shortest_first_period:.4g} s, "
                f"T_90 = {period_90:.4g} s) = {lower:.4g} s, upper bound 2 T_1 = {upper:.4g} s "
                f"(T_1 = {first_period:.4g} s)")
        return (lower, upper), note


RULES: dict[str, CodeRule] = {
    "asce7-22": CodeRule("asce7-22", "ASCE 7-22 16.2", 11, 1, 0.9, 1.1, "asce7-22"),
    "ec8": CodeRule("ec8", "EN 1998-1 3.2.3.1 / 4.3.3.4.3", 3, 7, 0.9, 0.9, "ec8", 10.0),
    "mean": CodeRule("mean", "plain mean (no code)", 1, 1, 1.0, 1.0, "asce7-22"),
}


