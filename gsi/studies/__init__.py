"""Study builders: whole cases (or set-ups) of one named study, built from the public case
API and run by :mod:`gsi.run`.

* :mod:`gsi.studies.drum`: the rotating drum of seed 003 (heat extrapolation);
* :mod:`gsi.studies.kiln`: the heated kiln, the drum turned inside an FE heat shell;
* :mod:`gsi.studies.bed_on_membrane`: a bed of particles at rest on a clamped membrane
  (the coupling's validation case);
* :mod:`gsi.studies.ensemble`: ensembles of a chaotic flow (sub-nanometre start
  perturbations), their members run side by side in worker processes.
"""
