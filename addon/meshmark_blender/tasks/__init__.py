"""The add-on's work, on Blender objects, without operators or panels.

Each task is a generator of steps (``yield fraction, text`` between pieces of work, ``return`` an
:class:`~.outcome.Outcome`): a modal operator runs one step per timer tick (progress in the status
bar, Esc stops between steps), a script runs them all at once (:func:`.outcome.run`). The pipeline API
(:mod:`meshmark_blender.api`) and the operators call the same tasks.

* :mod:`.watermark`: embed, verify, capacity and the automatic choice of parameters;
* :mod:`.frames`: verify over frames (the deformation study);
* :mod:`.copies`: issue marked copies, trace a copy;
* :mod:`.hiding`: hide and reveal data (steganography);
* :mod:`.inspect`: the precision heat map and steganalysis;
* :mod:`.study`: a study spec run in its own process.
"""
