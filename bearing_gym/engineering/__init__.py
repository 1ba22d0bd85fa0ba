"""The spindle engineer's tools, built on the env's physics: the preload map (which preload to run
at each operating point, with its margins; ``bearing-gym preload-map``)."""
