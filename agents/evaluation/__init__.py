"""Running policies on episodes: one batched loop for scripted and learned controllers
(:mod:`.episodes`), a policy's results (:mod:`.result`), trained SB3 models loaded and exported
for the portable path (:mod:`.trained`), one policy watched as it plays (:mod:`.watch`)."""
