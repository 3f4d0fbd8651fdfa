"""The Dyad library shipped with dyadc (installed as the package `compiler.components`).

Not Python code: the `.dyad` files below are the library. This file makes the folder a package so
that `importlib.resources.files("compiler.components")` finds it in every kind of install.
"""
