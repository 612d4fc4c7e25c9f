"""Number formatting shared by every text rendering: exact first, a decimal beside it."""

from __future__ import annotations

from fractions import Fraction

from maxplus.scalar import exact_text

__all__ = ["count", "human", "human_plain"]


def human(value: Fraction | None, unit: str) -> str:
    """``7/3 ms (2.333)``: exact, with a decimal beside it when not an integer."""
    if value is None:
        return "-"
    text = str(exact_text(value))
    if value.denominator != 1:
        text += f" {unit} ({float(value):.4g})"
    else:
        text += f" {unit}"
    return text


def human_plain(value: Fraction) -> str:
    """``7/3 (2.33333)``: exact, with a decimal beside it when not an integer (no unit)."""
    text = str(exact_text(value))
    return text if value.denominator == 1 else f"{text} ({float(value):.6g})"


def count(n: int, noun: str) -> str:
    """``1 state``, ``1,501 states``."""
    return f"{n:,} {noun}{'s' * (n != 1)}"
