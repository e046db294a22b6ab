# Tests
