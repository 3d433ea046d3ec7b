import railwear


def test_version_is_set():
    assert railwear.__version__.count(".") >= 2
