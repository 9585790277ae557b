"""One runtime package per mechanism: the class, its design spaces, synthesis problems and paper
procedures. Each exports ``MECHANISMS``; its module ``problems`` defines ``problems()``; :mod:`pkm.registry`
discovers both."""
