"""Plug-ins by name (layer 0): ``class X(Base, name="x")`` puts ``X`` in ``Base.registry``."""


class Registered:
    """A base whose subclasses register by name; each base holds its own ``registry`` dict."""

    registry: dict = {}
    name: str = ""

    def __init_subclass__(cls, name=None, **kwargs):
        super().__init_subclass__(**kwargs)
        if name is not None:
            cls.name = name
            cls.registry[name] = cls
