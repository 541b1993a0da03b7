"""Figures. The only package (with ``report`` and ``cli``) that imports matplotlib.

Every plotting function takes an optional matplotlib ``ax`` and returns the axes it drew on.
"""
