// io/cgal_adapter.hpp included first and alone: it compiles without the
// program including CGAL before it (built with the adapter's test, in its
// object library; a build error is the failure).
#include "nearcap/io/cgal_adapter.hpp"
