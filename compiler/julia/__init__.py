"""The Julia front end: reads the functions, structs and methods of a Dyad package's src/*.jl
(a subset of Julia, read as Dyad expression ASTs, never run) and applies them to Dyad values by
inlining. It imports nothing of compiler.model; the model's evaluator reaches it through its
registry of object calls (compiler/model/object_calls.py)."""
