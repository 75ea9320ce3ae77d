# Install rules for the wheel (pip / scikit-build-core, SKBUILD): the `edgedeform` package,
# i.e. the compiled _core module next to the Python sources, as in build/python/edgedeform.
install(TARGETS _core LIBRARY DESTINATION edgedeform)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/native/python/edgedeform/ DESTINATION edgedeform
        PATTERN __pycache__ EXCLUDE PATTERN *.pyc EXCLUDE)
