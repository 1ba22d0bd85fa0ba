"""The spindle engineer's tools, built on the env's physics: the preload map (which preload to run
at each operating point, with its margins; ``bearing-gym preload-map``) and the duty-cycle schedule
(a preload course for a machining cycle, checked on the model; ``bearing-gym schedule``)."""
