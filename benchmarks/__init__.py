"""Speed and accuracy measurements (tables and ``--json``), run as scripts
(``python benchmarks/bench_env.py``); the tests import the NumPy reference implementation and the
accuracy checks from here as ``benchmarks.numpy_reference`` and ``benchmarks.bench_accuracy``.
Not part of the installed package."""
