"""Post-processing of DEM results, outside the DEM core: Lacey's mixing index
(:mod:`gsi.post.mixing`) and the particle and contact Biot numbers (:mod:`gsi.post.biot`)."""
