"""Argument helpers shared by the subcommands: reading matrices and vectors in the CLI's text
form (``"a,b;c,d"``), exact unless a float literal with an exponent or ``--float`` asks otherwise."""

from __future__ import annotations

import argparse

import numpy as np

from ..numbers import parse_matrix, parse_number, parse_vector

__all__ = ["matrix_arg", "vector_arg", "number_arg", "add_json_flag"]


def add_json_flag(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print exactly one JSON object on stdout")


def matrix_arg(text: str, argument: str, *, as_float: bool = False):
    """Exact SymPy matrix from ``"a,b;c,d"``; a float array when ``as_float``."""
    m = parse_matrix(text, argument)
    return np.array(m.evalf(17).tolist(), dtype=float) if as_float else m


def vector_arg(text: str, argument: str, *, as_float: bool = False):
    v = parse_vector(text, argument)
    return np.array([float(x.evalf(17)) for x in v]) if as_float else v


def number_arg(text: str, argument: str, *, as_float: bool = False):
    x = parse_number(text, argument)
    return float(x.evalf(17)) if as_float else x
