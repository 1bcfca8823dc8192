// The registry hands each representation's functions its own packages (it dispatches on the
// package's representation name), so they take a Package& and know its type.
#pragma once

#include <standin/package.h>

#include <cassert>

namespace standin::reps {

// `package` as the representation's own package type; a package of another type is a programmer
// error.
template <class Own>
const Own& package_cast(const Package& package)
{
    assert(dynamic_cast<const Own*>(&package) && "a representation's function got another representation's package");
    return static_cast<const Own&>(package);
}

} // namespace standin::reps
