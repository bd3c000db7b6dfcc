"""The DEM contact model: sub-models in one file each, chosen by name.

- :mod:`~gsi.dem.contact.lanes`: the buffer of contacts the sub-models read and write;
- :mod:`~gsi.dem.contact.model`: the registries (normal, tangential, rolling, heat) and
  :func:`~gsi.dem.contact.model.evaluate`, the one function every contact goes through;
- normal sub-models :mod:`~gsi.dem.contact.hertz`, :mod:`~gsi.dem.contact.linear`;
  tangential :mod:`~gsi.dem.contact.tangential`; rolling :mod:`~gsi.dem.contact.rolling`;
  heat in :mod:`gsi.dem.contact.conductance`.

A sub-model is a compiled loop over lanes that reads only the buffer and its pair-table
row, so LLVM vectorizes it; it takes roots with :data:`gsi.jit.sqrt` (numba declares
libm's ``sqrt`` as writing errno, which keeps a loop from vectorizing).
"""
