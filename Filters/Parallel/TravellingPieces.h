/**
 * @file TravellingPieces.h
 * What a process sends of its piece to the others: the arrays a filter may light, and a
 * fingerprint that tells whether any process's piece changed since the last exchange.
 */
#ifndef TravellingPieces_h
#define TravellingPieces_h

#include "VolIllumParallelModule.h"

#include <cstddef>
#include <cstdint>

class vtkAbstractArray;
class vtkDataSet;

namespace volillum
{

/// Into `out` (a copy of the piece's structure): only the arrays a filter may light, shared
/// with `piece`: the array named `name` (nullptr or "" for none, in point or cell data), the
/// active scalars and the global ids. This is what travels.
VOLILLUMPARALLEL_EXPORT void CopyLitArrays(const char* name, vtkDataSet* piece, vtkDataSet* out);

/// FNV-1a over 8-byte words (then the last bytes), continuing from `hash`: a change detector,
/// at several GB/s.
VOLILLUMPARALLEL_EXPORT std::uint64_t HashBytes(const void* data, size_t size, std::uint64_t hash);

/// HashBytes over an array's type, size, name and values ("-" for none).
VOLILLUMPARALLEL_EXPORT std::uint64_t HashArray(vtkAbstractArray* array, std::uint64_t hash);

/// A fingerprint of what a process sends: its piece's structure and lit arrays. An update that
/// re-read an unchanged piece (readers may) keeps the assembled input and its classification.
VOLILLUMPARALLEL_EXPORT std::uint64_t Fingerprint(vtkDataSet* travelling);

}

#endif
